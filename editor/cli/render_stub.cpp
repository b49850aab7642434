// `plimsoll render` in builds without the renderer (PLIMSOLL_BUILD_EDITOR_GUI=OFF).
#include "cli/commands.h"

#include <iostream>

namespace plimsoll::cli {

void addRenderCommand(CLI::App& root, CommandRunner& selected) {
    CLI::App* cmd = root.add_subcommand("render", "Draw a project to a PNG (not in this build)");
    cmd->allow_extras();
    cmd->callback([&selected] {
        selected = [] {
            std::cerr << "error: this plimsoll was built without the renderer "
                         "(PLIMSOLL_BUILD_EDITOR_GUI=OFF)\n";
            return kExitFailure;
        };
    });
}

}  // namespace plimsoll::cli
