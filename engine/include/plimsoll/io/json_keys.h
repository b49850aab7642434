// JSON objects with a key given twice: nlohmann keeps the last silently, so a project with two
// "density" members would load one of them and show no sign of the other. Checked on the text
// before it is parsed, by the project and graph readers.
#pragma once

#include "plimsoll/core/result.h"

#include <string>

namespace plimsoll {

/// Ok, or "SOURCE: bodies[0]: the key "mesh" appears twice in one object" (the path of the
/// object in the document). Text that is not JSON is Ok here: the parser reports it.
Status checkNoDuplicateKeys(const std::string& text, const std::string& source);

}  // namespace plimsoll
