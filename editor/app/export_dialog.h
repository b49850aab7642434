// File > Export bundle...: runtime bundles of every body of the open project (docs/bundle.md),
// written by the engine's writeBodyBundle on a worker thread while a window shows progress and
// errors; the UI keeps drawing. The same bundles `plimsoll export PROJECT --out FOLDER` writes:
// FOLDER/<project file stem>/<body>/.
#pragma once

#include "plimsoll/project/project.h"

#include <filesystem>
#include <memory>
#include <string>

namespace plimsoll::editor {

/// Starts exporting `project` (a copy is taken) into `folder`. `unsaved`: the document has
/// changes not yet saved (the bundle is made from the project's files on disk, so the window
/// says they are not in it). Ignored, with a note in the window, while an export runs.
class ExportDialog;
std::shared_ptr<ExportDialog> makeExportDialog();

void startBundleExport(ExportDialog& dialog, const Project& project,
                       const std::filesystem::path& folder, bool unsaved);

/// Draws the export window while an export runs or its result is shown; every frame.
void drawBundleExport(ExportDialog& dialog);

/// Whether an export is running.
bool bundleExportRunning(const ExportDialog& dialog);

/// Whether the frame loop must keep drawing: an export runs, or its result is not on screen yet.
bool bundleExportNeedsFrames(const ExportDialog& dialog);

/// The export window's status line ("Exporting...", "Done: 1 bundle in 0.16 s"); "" when the
/// window is closed.
std::string bundleExportStatus(const ExportDialog& dialog);

}  // namespace plimsoll::editor
