// libFuzzer target: the runtime's PNG reader (the bundle's painted maps) on any bytes. It must
// refuse or decode, within the declared-size checks: no crash, no allocation beyond the limit.
#include "png.hpp"

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    plimsoll_runtime::GreyImage image;
    std::string error;
    if (!plimsoll_runtime::decodePng(bytes, image, error)) {
        if (error.empty()) std::abort();
        return 0;
    }
    if (image.width <= 0 || image.height <= 0 ||
        image.values.size() != static_cast<std::size_t>(image.width) * image.height)
        std::abort();
    for (float v : image.values)
        if (!(v >= 0.0f && v <= 1.0f)) std::abort();
    return 0;
}
