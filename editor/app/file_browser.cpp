#include "app/file_browser.h"

#include "app/tooltip.h"

#include <imgui.h>

#include <algorithm>
#include <cstring>

namespace plimsoll::editor {

namespace fs = std::filesystem;

namespace {

const char* title(FileBrowser::Purpose p) {
    switch (p) {
        case FileBrowser::Purpose::OpenProject:
            return "Open project";
        case FileBrowser::Purpose::SaveProjectAs:
            return "Save project as";
        case FileBrowser::Purpose::ImportMesh:
            return "Import mesh";
        case FileBrowser::Purpose::Export:
            return "Export to folder";
    }
    return "File";
}

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

void FileBrowser::open(Purpose purpose, const fs::path& folder, const std::string& name) {
    purpose_ = purpose;
    folder_ = folder.empty() ? fs::current_path() : folder;
    std::snprintf(name_, sizeof name_, "%s", name.c_str());
    namingFolder_ = false;
    error_.clear();
    requested_ = true;
    list();
}

bool FileBrowser::accepts(const fs::path& file) const {
    std::string name = file.filename().string();
    std::transform(name.begin(), name.end(), name.begin(), ::tolower);
    switch (purpose_) {
        case Purpose::OpenProject:
        case Purpose::SaveProjectAs:
            return endsWith(name, ".plim.json");
        case Purpose::ImportMesh:
            for (const char* ext :
                 {".obj", ".fbx", ".gltf", ".glb", ".ply", ".stl", ".dae", ".3ds"}) {
                if (endsWith(name, ext)) return true;
            }
            return false;
        case Purpose::Export:
            return false;
    }
    return false;
}

void FileBrowser::list() {
    entries_.clear();
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(folder_, ec)) {
        const std::string name = e.path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        const bool folder = e.is_directory(ec);
        if (folder || accepts(e.path())) entries_.push_back({name, folder});
    }
    if (ec) error_ = folder_.string() + ": " + ec.message();
    std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
        return a.folder != b.folder ? a.folder : a.name < b.name;
    });
}

std::optional<fs::path> FileBrowser::draw() {
    const char* id = title(purpose_);
    if (requested_) {
        ImGui::OpenPopup(id);
        requested_ = false;
    }
    std::optional<fs::path> chosen;
    ImGui::SetNextWindowSize(ImVec2(640, 440), ImGuiCond_Appearing);
    if (!ImGui::BeginPopupModal(id, nullptr)) return chosen;
    ImGui::TextUnformatted(folder_.string().c_str());
    const bool up = ImGui::Button("Up");
    tooltip("The folder that holds this one.");
    if (up && folder_.has_parent_path()) {
        folder_ = folder_.parent_path();
        list();
    }
    ImGui::SameLine();
    const bool home = ImGui::Button("Home");
    tooltip("Your home folder ($HOME).");
    if (home) {
        if (const char* home = std::getenv("HOME")) folder_ = home;
        list();
    }
    ImGui::SameLine();
    const bool current = ImGui::Button("Current folder");
    tooltip("The folder the editor was started in.");
    if (current) {
        folder_ = fs::current_path();
        list();
    }
    ImGui::SameLine();
    const bool newFolder = ImGui::Button("New folder");
    tooltip("Makes a folder here: type its name, then Create or Enter.");
    if (newFolder) {
        namingFolder_ = true;
        folderName_[0] = '\0';
    }
    if (namingFolder_) {
        ImGui::SetNextItemWidth(240);
        const bool entered = ImGui::InputText("##folder", folderName_, sizeof folderName_,
                                              ImGuiInputTextFlags_EnterReturnsTrue);
        ImGui::SameLine();
        const bool create = ImGui::Button("Create");
        tooltip("Creates the folder and opens it.");
        if ((create || entered) && folderName_[0]) {
            std::error_code ec;
            const fs::path made = folder_ / folderName_;
            if (fs::create_directory(made, ec)) {
                folder_ = made;
                namingFolder_ = false;
                list();
            } else {
                error_ =
                    made.string() + ": cannot create" + (ec ? ": " + ec.message() : " (it exists)");
            }
        }
    }
    const float footer = ImGui::GetFrameHeightWithSpacing() * 2.2f;
    ImGui::BeginChild("entries", ImVec2(0, -footer), true);
    for (const Entry& e : entries_) {
        const std::string label = (e.folder ? "[dir] " : "      ") + e.name;
        const bool picked = ImGui::Selectable(label.c_str(), !e.folder && e.name == name_,
                                              ImGuiSelectableFlags_AllowDoubleClick);
        tooltip(e.folder ? "Click to open the folder."
                         : "Click to choose the file, double-click to take it.");
        if (picked) {
            if (e.folder) {
                folder_ /= e.name;
                list();
                break;
            }
            std::snprintf(name_, sizeof name_, "%s", e.name.c_str());
            if (ImGui::IsMouseDoubleClicked(0)) chosen = folder_ / e.name;
        }
    }
    ImGui::EndChild();
    if (!error_.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", error_.c_str());
    bool entered = false;
    if (purpose_ != Purpose::Export) {
        // The name has the keys when the dialog opens, as in Blender's and the desktop's file
        // dialogs: type a name, Enter saves or opens.
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        ImGui::SetNextItemWidth(-200);
        entered = ImGui::InputText(
            "##name", name_, sizeof name_,
            ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
        tooltip("The file's name in this folder, or a whole path; Enter takes it.");
        ImGui::SameLine();
    }
    const char* action = purpose_ == Purpose::SaveProjectAs ? "Save"
                         : purpose_ == Purpose::Export      ? "Export here"
                                                            : "Open";
    const bool act = ImGui::Button(action);
    tooltip(purpose_ == Purpose::SaveProjectAs
                ? "Saves the project under this name (its maps and graphs beside it)."
            : purpose_ == Purpose::Export ? "Exports the bundle into the folder shown above."
                                          : "Opens the chosen file.");
    if (act || entered) {
        if (purpose_ == Purpose::Export)
            chosen = folder_;
        else if (name_[0])
            chosen = fs::path(name_).is_absolute() ? fs::path(name_) : folder_ / name_;
    }
    ImGui::SameLine();
    const bool cancel = ImGui::Button("Cancel");
    tooltip("Closes the dialog; nothing is written (Esc).");
    if (cancel || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape)))
        ImGui::CloseCurrentPopup();
    if (chosen) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
    return chosen;
}

}  // namespace plimsoll::editor
