// Stand-in for the editor window in builds without the GUI (PLIMSOLL_BUILD_EDITOR_GUI=OFF).
#include "app/editor_app.h"

#include <iostream>

namespace plimsoll::editor {

int runEditorWindow(const EditorLaunch&) {
    std::cerr << "error: this plimsoll was built without the editor window "
                 "(PLIMSOLL_BUILD_EDITOR_GUI=OFF); use the sub-commands, or edit --script\n";
    return 1;
}

}  // namespace plimsoll::editor
