// plimsoll: the editor (no sub-command) and the headless command line (a sub-command), in one
// executable like `blender -b`. Sub-commands live one per file in cli/.
#include "app/editor_app.h"
#include "cli/commands.h"

#include <exception>
#include <new>
#include <iostream>

int main(int argc, char** argv) {
    using namespace plimsoll::cli;
    CLI::App app{
        "Plimsoll: real-time buoyancy from surface textures.\n"
        "Run a sub-command for headless work (plimsoll SUBCOMMAND --help).",
        "plimsoll"};
    app.set_version_flag("--version", std::string("plimsoll ") + PLIMSOLL_VERSION);
    app.require_subcommand(0, 1);
    CommandRunner selected;
    addValidateCommand(app, selected);
    addBakeCommand(app, selected);
    addMassPropsCommand(app, selected);
    addSamplesCommand(app, selected);
    addBenchCommand(app, selected);
    addBuoyancyCommand(app, selected);
    addSimulateCommand(app, selected);
    addGraphCommand(app, selected);
    addAtlasCommand(app, selected);
    addExportCommand(app, selected);
    addEditCommand(app, selected);
    addRenderCommand(app, selected);
    addHydrostaticsCommand(app, selected);
    addHydroCommand(app, selected);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11's own codes (105 for a failed check, ...) are not the documented usage exit.
        return app.exit(e) == 0 ? kExitOk : kExitUsage;
    }
    if (!selected) {
        // No sub-command: the editor window (`plimsoll edit` with no project).
        return plimsoll::editor::runEditorWindow({});
    }
    try {
        return selected();
    } catch (const std::bad_alloc&) {
        std::cerr << "error: out of memory: the input needs more memory than this machine can "
                     "give (std::bad_alloc)\n";
        return kExitFailure;
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return kExitFailure;
    }
}
