// A file browser drawn with ImGui (Debian ships no native dialog library the editor could use):
// folders first, files filtered by what the purpose accepts, a name field for saving.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::editor {

class FileBrowser {
public:
    enum class Purpose { OpenProject, SaveProjectAs, ImportMesh, Export };

    /// Shows the browser (as a modal popup) from the next frame, in `folder`, with `name` in
    /// the name field (saving: the document's own name rather than a generic one).
    void open(Purpose purpose, const std::filesystem::path& folder, const std::string& name = "");
    /// Draws it while open; returns the chosen path on the frame it is chosen.
    std::optional<std::filesystem::path> draw();
    Purpose purpose() const { return purpose_; }

private:
    void list();
    bool accepts(const std::filesystem::path& file) const;

    struct Entry {
        std::string name;
        bool folder = false;
    };
    bool requested_ = false;
    Purpose purpose_ = Purpose::OpenProject;
    std::filesystem::path folder_;
    std::vector<Entry> entries_;
    char name_[512] = {};
    std::string error_;
    bool namingFolder_ = false;  ///< "New folder" is asking for a name
    char folderName_[256] = {};
};

}  // namespace plimsoll::editor
