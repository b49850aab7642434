// Edit scripts: a JSON list of commands run against a document without a window
// (`plimsoll edit PROJECT --script commands.json`), so every editing feature is testable
// headless. The format is written down in docs/edit-scripts.md.
#pragma once

#include "document/document.h"

#include <nlohmann/json.hpp>

namespace plimsoll::editor {

/// Runs the script's commands in order. Returns one result object per command (what it did, or
/// a picked value); stops at the first command that fails, naming its index.
Result<nlohmann::json> runEditScript(Document& document, const nlohmann::json& script);

}  // namespace plimsoll::editor
