// libFuzzer target: project JSON text (parseProject). Any input must give a project or an
// error, never a crash; a project that parses must survive projectToJson and parse back equal
// (a saved project that cannot be opened again would lose work).
#include "plimsoll/project/project.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::filesystem::path folder = "/nonexistent-plimsoll-fuzz";
    plimsoll::Result<plimsoll::Project> project =
        plimsoll::parseProject(text, "fuzz.plim.json", folder);
    if (!project) {
        if (project.error().message.empty()) std::abort();  // every error says what is wrong
        return 0;
    }
    const std::string saved = plimsoll::projectToJson(*project);
    plimsoll::Result<plimsoll::Project> again =
        plimsoll::parseProject(saved, "saved.plim.json", folder);
    if (!again) {
        std::fprintf(stderr, "saved project does not load: %s\n%s\n", again.error().message.c_str(),
                     saved.c_str());
        std::abort();
    }
    if (!(*again == *project)) {
        std::fprintf(stderr, "saved project loads different:\n%s\n", saved.c_str());
        std::abort();
    }
    return 0;
}
