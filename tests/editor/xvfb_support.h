// The command prefix that runs an editor window under its own Xvfb (window tests).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace plimsoll::test {

/// `xvfb-run` with a config folder of its own under `dir` (no recent files or autosaves of
/// the user's) and a display number of its own. `xvfb-run -a` alone searches from display 99,
/// so two window tests started at the same moment (ctest --parallel) could take the same
/// number; one X server then failed and its test skipped without a word. The search starts
/// at a number taken from the process id instead (each ctest test is a process of its own).
inline std::string xvfbRun(const std::filesystem::path& dir) {
    const int start = 100 + static_cast<int>(::getpid() % 2000) * 4;
    return "XDG_CONFIG_HOME='" + (dir / "config").string() + "' xvfb-run -a -n " +
           std::to_string(start) + " -s '-screen 0 1280x800x24'";
}

}  // namespace plimsoll::test
