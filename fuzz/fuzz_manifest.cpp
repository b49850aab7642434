// libFuzzer target: runtime bundle manifest text (parseBundleManifest, the part of verifyBundle
// that reads the manifest). Any input gives the manifest's facts or an error; a manifest that
// passes never lists a path that leaves the bundle.
#include "plimsoll/export/bundle.h"

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    plimsoll::Result<plimsoll::BundleManifestInfo> info =
        plimsoll::parseBundleManifest(text, "manifest.json");
    if (!info) {
        if (info.error().message.empty()) std::abort();
        return 0;
    }
    for (const plimsoll::BundleFile& f : info->files) {
        const std::filesystem::path p(f.path);
        if (f.path.empty() || p.is_absolute()) std::abort();
        for (const auto& part : p)
            if (part == "..") std::abort();
    }
    return 0;
}
