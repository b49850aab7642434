#include "plimsoll/file_util.h"

#include <fstream>
#include <system_error>
#include <unistd.h>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {
BeforeReplaceHook& beforeReplaceHook() {
    static BeforeReplaceHook hook;
    return hook;
}
}  // namespace

void setBeforeReplaceHookForTesting(BeforeReplaceHook hook) {
    beforeReplaceHook() = std::move(hook);
}

fs::path temporaryPathFor(const fs::path& target) {
    fs::path dir = target.parent_path();
    std::string name = "." + target.filename().string() + ".tmp" + std::to_string(::getpid());
    return dir.empty() ? fs::path(name) : dir / name;
}

Status replaceFileAtomically(const fs::path& target,
                             const std::function<Status(const fs::path&)>& write) {
    const fs::path temp = temporaryPathFor(target);
    Status written = write(temp);
    std::error_code ec;
    if (!written.ok()) {
        fs::remove(temp, ec);
        return written;
    }
    if (beforeReplaceHook()) beforeReplaceHook()(temp, target);
    fs::rename(temp, target, ec);
    if (ec) {
        fs::remove(temp, ec);
        return makeError(target.string() + ": cannot replace file: " + ec.message());
    }
    return Ok{};
}

Status writeFileAtomically(const fs::path& target,
                           const std::function<bool(std::ostream&)>& write) {
    return replaceFileAtomically(target, [&](const fs::path& temp) -> Status {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) return makeError(target.string() + ": cannot open for writing");
        if (!write(out)) return makeError(target.string() + ": write abandoned");
        out.flush();
        if (!out) return makeError(target.string() + ": write failed (disk full?)");
        return Ok{};
    });
}

}  // namespace plimsoll
