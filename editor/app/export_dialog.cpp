// File > Export bundle... (export_dialog.h). The worker thread owns a copy of the project and
// touches nothing else of the editor; it reports through a mutex-guarded log the window reads.
#include "app/export_dialog.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/io/file_util.h"

#include "app/tooltip.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace plimsoll::editor {

namespace fs = std::filesystem;

namespace {

struct Progress {
    std::mutex mutex;
    std::vector<std::string> lines;  ///< notices, one line per body, errors
    std::size_t done = 0, total = 0;
    std::string current;  ///< the body being exported
    bool finished = false;
    int failures = 0;
    /// The worker's own clock: the time the export took is its, not the frame loop's (an
    /// idle loop may draw the result much later).
    std::chrono::steady_clock::time_point started, finishedAt;
};

}  // namespace

class ExportDialog {
public:
    ~ExportDialog() {
        if (worker_.joinable()) worker_.join();  // a bundle is never left half swapped
    }

    void start(const Project& project, const fs::path& folder, bool unsaved) {
        if (running()) {
            std::lock_guard lock(progress_->mutex);
            progress_->lines.push_back("an export is running: wait for it to finish");
            visible_ = true;
            return;
        }
        if (worker_.joinable()) worker_.join();
        progress_ = std::make_shared<Progress>();
        progress_->total = project.bodies.size();
        target_ = folder / safeFileName(project.fileStem, "project");
        if (unsaved)
            progress_->lines.push_back(
                "note: unsaved changes are not in the bundle (it is made "
                "from the saved project's files); save and export again "
                "to include them");
        if (project.folder.empty())
            progress_->lines.push_back(
                "note: the project was never saved: relative paths are "
                "taken from the current folder");
        visible_ = true;
        shown_ = false;
        progress_->started = std::chrono::steady_clock::now();
        worker_ = std::thread([p = progress_, project, target = target_] {
            for (std::size_t b = 0; b < project.bodies.size(); ++b) {
                const fs::path bundle = target / bundleFolderName(project, b);
                {
                    std::lock_guard lock(p->mutex);
                    p->current = project.bodies[b].name;
                }
                auto log = [&p](const std::string& line) {
                    std::lock_guard lock(p->mutex);
                    p->lines.push_back(line);
                };
                Result<BundleReport> r = writeBodyBundle(project, b, bundle, log);
                std::lock_guard lock(p->mutex);
                if (r) {
                    p->lines.push_back(bundle.string() + ": " + std::to_string(r->files.size()) +
                                       " files, " + std::to_string(r->totalBytes() / 1024) +
                                       " KiB");
                } else {
                    p->lines.push_back("error: " + r.error().message);
                    ++p->failures;
                }
                ++p->done;
            }
            {
                std::lock_guard lock(p->mutex);
                p->finished = true;
                p->finishedAt = std::chrono::steady_clock::now();
                p->current.clear();
            }
            glfwPostEmptyEvent();  // wakes an idle frame loop to show the result now
        });
    }

    bool running() const {
        if (!progress_) return false;
        std::lock_guard lock(progress_->mutex);
        return !progress_->finished;
    }

    /// Running, or finished and not yet drawn so: the frame loop keeps drawing until the
    /// window shows the result.
    bool needsFrames() const { return running() || (progress_ && visible_ && !shown_); }

    /// The line under the progress bar ("" with no export window).
    std::string status() const {
        if (!visible_ || !progress_) return "";
        std::lock_guard lock(progress_->mutex);
        return statusLine(*progress_);
    }

    void draw() {
        if (!visible_ || !progress_) return;
        ImGui::SetNextWindowSize(ImVec2(560, 300), ImGuiCond_Appearing);
        bool open = true;
        if (!ImGui::Begin("Export bundle", &open)) {
            ImGui::End();
            shown_ = !running();  // collapsed: nothing more to draw
            if (!open && !running()) visible_ = false;
            return;
        }
        Progress& p = *progress_;
        std::lock_guard lock(p.mutex);
        ImGui::TextUnformatted(target_.string().c_str());
        const float fraction = p.total ? static_cast<float>(p.done) / p.total : 1.0f;
        const std::string label = std::to_string(p.done) + " / " + std::to_string(p.total) +
                                  (p.current.empty() ? std::string() : "  " + p.current);
        ImGui::ProgressBar(fraction, ImVec2(-1, 0), label.c_str());
        const std::string line = statusLine(p);
        if (p.failures && p.finished) {
            ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", line.c_str());
        } else {
            ImGui::TextUnformatted(line.c_str());
        }
        shown_ = p.finished;
        ImGui::Separator();
        ImGui::BeginChild("log", ImVec2(0, -ImGui::GetFrameHeightWithSpacing()), false,
                          ImGuiWindowFlags_HorizontalScrollbar);
        for (const std::string& line : p.lines) {
            const bool error = line.rfind("error:", 0) == 0;
            if (error) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.3f, 1.0f));
            ImGui::TextUnformatted(line.c_str());
            if (error) ImGui::PopStyleColor();
        }
        ImGui::EndChild();
        ImGui::BeginDisabled(!p.finished);
        if (ImGui::Button("Close")) open = false;
        tooltip("Closes the log (once the export has finished).");
        ImGui::EndDisabled();
        ImGui::End();
        if (!open && p.finished) visible_ = false;
    }

private:
    std::shared_ptr<Progress> progress_;
    std::thread worker_;
    fs::path target_;
    bool visible_ = false;
    bool shown_ = false;  ///< a frame has drawn the finished export

    static std::string statusLine(const Progress& p) {
        if (!p.finished) return "Exporting...";
        if (p.failures)
            return std::to_string(p.failures) + " of " + std::to_string(p.total) + " bodies failed";
        const double seconds = std::chrono::duration<double>(p.finishedAt - p.started).count();
        char text[96];
        std::snprintf(text, sizeof text, "Done: %zu %s in %.2f s", p.total,
                      p.total == 1 ? "bundle" : "bundles", seconds);
        return text;
    }
};

std::shared_ptr<ExportDialog> makeExportDialog() { return std::make_shared<ExportDialog>(); }

void startBundleExport(ExportDialog& dialog, const Project& project, const fs::path& folder,
                       bool unsaved) {
    dialog.start(project, folder, unsaved);
}

void drawBundleExport(ExportDialog& dialog) { dialog.draw(); }

bool bundleExportRunning(const ExportDialog& dialog) { return dialog.running(); }

bool bundleExportNeedsFrames(const ExportDialog& dialog) { return dialog.needsFrames(); }

std::string bundleExportStatus(const ExportDialog& dialog) { return dialog.status(); }

}  // namespace plimsoll::editor
