#include "exr_io.h"

#include "plimsoll/limits.h"

#include "plimsoll/file_util.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <exception>

namespace plimsoll::detail {

namespace fs = std::filesystem;

namespace {
Imf::FrameBuffer frameBufferFor(FloatImage& image) {
    Imf::FrameBuffer buffer;
    const std::size_t stride = image.channels.size() * sizeof(float);
    char* base = reinterpret_cast<char*>(image.pixels.data());
    for (std::size_t c = 0; c < image.channels.size(); ++c) {
        buffer.insert(image.channels[c],
                      Imf::Slice(Imf::FLOAT, base + c * sizeof(float), stride,
                                 stride * static_cast<std::size_t>(image.width)));
    }
    return buffer;
}
}  // namespace

Status writeExrFile(const fs::path& file, const FloatImage& image, const fs::path& target) {
    try {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const auto& name : image.channels) {
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        }
        Imf::OutputFile out(file.c_str(), header);
        FloatImage& writable = const_cast<FloatImage&>(image);  // Slice wants char*
        out.setFrameBuffer(frameBufferFor(writable));
        out.writePixels(image.height);
    } catch (const std::exception& e) {
        return makeError(target.string() + ": cannot write EXR: " + e.what());
    }
    return Ok{};
}

Status writeExr(const fs::path& path, const FloatImage& image) {
    return replaceFileAtomically(
        path, [&](const fs::path& temp) { return writeExrFile(temp, image, path); });
}

Status writeExr(const fs::path& path, const UintImage& image) {
    return replaceFileAtomically(path, [&](const fs::path& temp) -> Status {
        try {
            Imf::Header header(image.width, image.height);
            header.compression() = Imf::ZIP_COMPRESSION;
            header.channels().insert(image.channel, Imf::Channel(Imf::UINT));
            Imf::OutputFile file(temp.c_str(), header);
            Imf::FrameBuffer buffer;
            char* base = reinterpret_cast<char*>(const_cast<std::uint32_t*>(image.pixels.data()));
            buffer.insert(image.channel,
                          Imf::Slice(Imf::UINT, base, sizeof(std::uint32_t),
                                     sizeof(std::uint32_t) * static_cast<std::size_t>(image.width)));
            file.setFrameBuffer(buffer);
            file.writePixels(image.height);
        } catch (const std::exception& e) {
            return makeError(path.string() + ": cannot write EXR: " + e.what());
        }
        return Ok{};
    });
}

Result<UintImage> readExrUint(const fs::path& path, const std::string& channel) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        if (window.min.x != 0 || window.min.y != 0) {
            return makeError(path.string() + ": EXR data window does not start at (0, 0)");
        }
        const Imf::Channel* found = file.header().channels().findChannel(channel);
        if (!found) return makeError(path.string() + ": EXR has no channel '" + channel + "'");
        if (found->type != Imf::UINT) {
            return makeError(path.string() + ": EXR channel '" + channel + "' is not UINT");
        }
        UintImage image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        image.channel = channel;
        image.pixels.assign(static_cast<std::size_t>(image.width) * image.height, 0u);
        Imf::FrameBuffer buffer;
        buffer.insert(channel, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(image.pixels.data()),
                                          sizeof(std::uint32_t),
                                          sizeof(std::uint32_t) * static_cast<std::size_t>(image.width)));
        file.setFrameBuffer(buffer);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const std::exception& e) {
        return makeError(path.string() + ": cannot read EXR: " + e.what());
    }
}

Result<FloatImage> readExr(const fs::path& path, const std::vector<std::string>& channels) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        FloatImage image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        image.channels = channels;
        if (window.min.x != 0 || window.min.y != 0) {
            return makeError(path.string() + ": EXR data window does not start at (0, 0)");
        }
        for (const auto& name : channels) {
            if (!file.header().channels().findChannel(name)) {
                return makeError(path.string() + ": EXR has no channel '" + name + "'");
            }
        }
        // The header's size is checked before the pixels are allocated: a corrupt or hostile
        // header could ask for terabytes. Baked images are N x N (N <= kMaxTextureSize) and the
        // sample list holds a few entries per texel.
        const std::uint64_t pixels = std::uint64_t(image.width) * std::uint64_t(image.height);
        constexpr std::uint64_t kMaxPixels = 4ull * kMaxTextureSize * kMaxTextureSize;
        if (image.width <= 0 || image.height <= 0 || pixels > kMaxPixels) {
            return makeError(path.string() + ": EXR of " + std::to_string(image.width) + " x " +
                             std::to_string(image.height) + " pixels: more than the limit of " +
                             std::to_string(kMaxPixels) +
                             " (4 x kMaxTextureSize^2, limits.h), or empty");
        }
        image.pixels.assign(static_cast<std::size_t>(image.width) * image.height *
                                channels.size(), 0.0f);
        file.setFrameBuffer(frameBufferFor(image));
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const std::exception& e) {
        return makeError(path.string() + ": cannot read EXR: " + e.what());
    }
}

}  // namespace plimsoll::detail
