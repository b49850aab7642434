#include "io/exr_io.h"

#include "plimsoll/core/limits.h"

#include "plimsoll/io/file_util.h"

#include "io/temporary_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <Imath/half.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <functional>
#include <stdexcept>
#include <unistd.h>

namespace plimsoll::detail {

namespace fs = std::filesystem;

namespace {
/// The header's size is checked before the pixels are allocated: a corrupt or hostile header
/// could ask for terabytes. Baked images are N x N (N <= kMaxTextureSize) and the sample list
/// holds a few entries per texel.
Status checkExrSize(const fs::path& path, int width, int height) {
    const std::uint64_t pixels =
        std::uint64_t(std::max(width, 0)) * std::uint64_t(std::max(height, 0));
    constexpr std::uint64_t kMaxPixels = 4ull * kMaxTextureSize * kMaxTextureSize;
    if (width <= 0 || height <= 0 || pixels > kMaxPixels) {
        return makeError(ErrorKind::limit, path.string() + ": EXR of " + std::to_string(width) +
                                               " x " + std::to_string(height) +
                                               " pixels: more than the limit of " +
                                               std::to_string(kMaxPixels) +
                                               " (4 x kMaxTextureSize^2, limits.h), or empty");
    }
    return Ok{};
}

/// OpenEXR's output written through a descriptor, not a name: the temporary is opened by
/// openTemporaryForWriting (no link followed, no other file's name), and OpenEXR never opens a
/// path itself. Write errors throw, as OpenEXR's own streams do.
class DescriptorStream : public Imf::OStream {
public:
    DescriptorStream(int fd, const fs::path& target) : Imf::OStream(target.c_str()), fd_(fd) {}
    ~DescriptorStream() override { ::close(fd_); }
    DescriptorStream(const DescriptorStream&) = delete;
    DescriptorStream& operator=(const DescriptorStream&) = delete;

    void write(const char c[], int n) override {
        for (int done = 0; done < n;) {
            const ssize_t k = ::write(fd_, c + done, static_cast<std::size_t>(n - done));
            if (k < 0 && errno == EINTR) continue;
            if (k <= 0)
                throw std::runtime_error(std::string("write failed: ") +
                                         std::strerror(k < 0 ? errno : ENOSPC));
            done += static_cast<int>(k);
        }
    }
    std::uint64_t tellp() override {
        const off_t at = ::lseek(fd_, 0, SEEK_CUR);
        if (at < 0) throw std::runtime_error("cannot tell the write position");
        return static_cast<std::uint64_t>(at);
    }
    void seekp(std::uint64_t pos) override {
        if (::lseek(fd_, static_cast<off_t>(pos), SEEK_SET) < 0)
            throw std::runtime_error("cannot seek");
    }
    /// Flushed to the disk before the rename makes the file the target.
    void sync() {
        if (::fdatasync(fd_) != 0)
            throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
    }

private:
    int fd_;
};

/// Writes an EXR with `header` into the temporary `file` for `target`: `write` hands OpenEXR
/// the pixels.
Status writeExrThroughDescriptor(const fs::path& file, const fs::path& target,
                                 const Imf::Header& header,
                                 const std::function<void(Imf::OutputFile&)>& write) {
    Result<int> fd = openTemporaryForWriting(file, target);
    if (!fd) return fd.error();
    DescriptorStream stream(*fd, target);
    try {
        {
            Imf::OutputFile out(stream, header);
            write(out);
        }  // the line offset table is written when the file closes
        stream.sync();
    } catch (const std::exception& e) {
        return makeError(ErrorKind::io, target.string() + ": cannot write EXR: " + e.what());
    }
    return Ok{};
}

Status writeExrThroughDescriptor(const fs::path& file, const fs::path& target,
                                 const Imf::Header& header, const Imf::FrameBuffer& buffer,
                                 int rows) {
    return writeExrThroughDescriptor(file, target, header, [&](Imf::OutputFile& out) {
        out.setFrameBuffer(buffer);
        out.writePixels(rows);
    });
}

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
    // As rows: whole images and streamed ones go through the one writer below.
    const std::size_t stride = static_cast<std::size_t>(image.width) * image.channels.size();
    const FloatRows rows{image.width, image.height, image.channels,
                         [&](float* out, int first, int count) {
                             std::copy_n(image.pixels.data() + first * stride, count * stride, out);
                         },
                         image.half};
    return writeExrFile(file, rows, target);
}

Status writeExrFile(const fs::path& file, const FloatRows& image, const fs::path& target) {
    const std::size_t channels = image.channels.size();
    auto isHalf = [&](std::size_t c) { return c < image.half.size() && image.half[c]; };
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    for (std::size_t c = 0; c < channels; ++c)
        header.channels().insert(image.channels[c],
                                 Imf::Channel(isHalf(c) ? Imf::HALF : Imf::FLOAT));
    const std::size_t stride = channels * sizeof(float);
    // Blocks of rows a multiple of ZIP's 16-line chunks, about 8 MB at the widest texture.
    constexpr int kBlockRows = 64;
    return writeExrThroughDescriptor(file, target, header, [&](Imf::OutputFile& out) {
        std::vector<float> block;
        std::vector<std::vector<Imath::half>> halves(channels);
        for (int first = 0; first < image.height; first += kBlockRows) {
            const int count = std::min(kBlockRows, image.height - first);
            const std::size_t pixels = static_cast<std::size_t>(count) * image.width;
            block.assign(pixels * channels, 0.0f);
            image.fill(block.data(), first, count);
            Imf::FrameBuffer buffer;
            for (std::size_t c = 0; c < channels; ++c) {
                // The block holds rows first.. first + count: its origin is (0, first).
                if (!isHalf(c)) {
                    buffer.insert(
                        image.channels[c],
                        Imf::Slice::Make(Imf::FLOAT, block.data() + c, Imath::V2i(0, first),
                                         image.width, count, stride, stride * image.width));
                    continue;
                }
                // OpenEXR converts pixel types when reading, not when writing: a HALF channel
                // is given half pixels of its own (rounded to nearest, as Imath's half does).
                halves[c].resize(pixels);
                for (std::size_t i = 0; i < pixels; ++i)
                    halves[c][i] = Imath::half(block[i * channels + c]);
                buffer.insert(image.channels[c],
                              Imf::Slice::Make(Imf::HALF, halves[c].data(), Imath::V2i(0, first),
                                               image.width, count, sizeof(Imath::half),
                                               sizeof(Imath::half) * image.width));
            }
            out.setFrameBuffer(buffer);
            out.writePixels(count);
        }
    });
}

Status writeExr(const fs::path& path, const FloatImage& image) {
    return replaceFileAtomically(
        path, [&](const fs::path& temp) { return writeExrFile(temp, image, path); });
}

Status writeExr(const fs::path& path, const UintImage& image) {
    return replaceFileAtomically(path, [&](const fs::path& temp) -> Status {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        header.channels().insert(image.channel, Imf::Channel(Imf::UINT));
        Imf::FrameBuffer buffer;
        char* base = reinterpret_cast<char*>(const_cast<std::uint32_t*>(image.pixels.data()));
        buffer.insert(image.channel,
                      Imf::Slice(Imf::UINT, base, sizeof(std::uint32_t),
                                 sizeof(std::uint32_t) * static_cast<std::size_t>(image.width)));
        return writeExrThroughDescriptor(temp, path, header, buffer, image.height);
    });
}

Result<UintImage> readExrUint(const fs::path& path, const std::string& channel) {
    // OpenEXR opens the file itself: refuse a FIFO or a device before it can block or stream.
    if (Status regular = checkRegularFile(path); !regular.ok()) return regular.error();
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        if (window.min.x != 0 || window.min.y != 0) {
            return makeError(ErrorKind::format,
                             path.string() + ": EXR data window does not start at (0, 0)");
        }
        const Imf::Channel* found = file.header().channels().findChannel(channel);
        if (!found)
            return makeError(ErrorKind::format,
                             path.string() + ": EXR has no channel '" + channel + "'");
        if (found->type != Imf::UINT) {
            return makeError(ErrorKind::format,
                             path.string() + ": EXR channel '" + channel + "' is not UINT");
        }
        UintImage image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        image.channel = channel;
        if (Status size = checkExrSize(path, image.width, image.height); !size.ok())
            return size.error();
        image.pixels.assign(static_cast<std::size_t>(image.width) * image.height, 0u);
        Imf::FrameBuffer buffer;
        buffer.insert(channel,
                      Imf::Slice(Imf::UINT, reinterpret_cast<char*>(image.pixels.data()),
                                 sizeof(std::uint32_t),
                                 sizeof(std::uint32_t) * static_cast<std::size_t>(image.width)));
        file.setFrameBuffer(buffer);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const std::exception& e) {
        return makeError(ErrorKind::format, path.string() + ": cannot read EXR: " + e.what());
    }
}

Result<FloatImage> readExr(const fs::path& path, const std::vector<std::string>& channels) {
    if (Status regular = checkRegularFile(path); !regular.ok()) return regular.error();
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        FloatImage image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        image.channels = channels;
        if (window.min.x != 0 || window.min.y != 0) {
            return makeError(ErrorKind::format,
                             path.string() + ": EXR data window does not start at (0, 0)");
        }
        for (const auto& name : channels) {
            if (!file.header().channels().findChannel(name)) {
                return makeError(ErrorKind::format,
                                 path.string() + ": EXR has no channel '" + name + "'");
            }
        }
        if (Status size = checkExrSize(path, image.width, image.height); !size.ok())
            return size.error();
        image.pixels.assign(static_cast<std::size_t>(image.width) * image.height * channels.size(),
                            0.0f);
        file.setFrameBuffer(frameBufferFor(image));
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const std::exception& e) {
        return makeError(ErrorKind::format, path.string() + ": cannot read EXR: " + e.what());
    }
}

}  // namespace plimsoll::detail
