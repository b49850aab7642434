// Runs the plimsoll executable for end-to-end tests: exit code, stdout and stderr.
#pragma once

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace plimsoll::test {

struct CommandOutput {
    int exitCode = -1;
    std::string out;
    std::string err;
};

/// A `plimsoll render` run that found no renderer: no EGL with OpenGL 4.5, or a build without
/// the GUI.
inline bool cannotRender(const CommandOutput& r) {
    return r.exitCode != 0 && (r.err.find("no OpenGL 4.5 context") != std::string::npos ||
                               r.err.find("without the renderer") != std::string::npos);
}

/// The plimsoll executable of the build this test binary belongs to (build/tests/plimsoll_tests
/// runs build/editor/plimsoll). Found at run time rather than compiled in, so that the test
/// sources compile to the same objects in every build folder (ccache hits across them).
inline std::filesystem::path plimsollExecutable() {
    namespace fs = std::filesystem;
    return fs::read_symlink("/proc/self/exe").parent_path().parent_path() / "editor" / "plimsoll";
}

/// A command prefix that caps the memory a plimsoll run may take at `bytes`. Normally an
/// address-space limit (prlimit --as), which turns a runaway allocation into std::bad_alloc.
/// AddressSanitizer reserves terabytes of address space for its shadow at start-up, so there
/// an address-space limit stops every run before main; the sanitized build caps the resident
/// set instead (ASan kills a run above hard_rss_limit_mb, which fails the test as a finding).
/// Either way a command word, so that it may follow `timeout`.
inline std::string memoryCap(unsigned long long bytes) {
#ifdef PLIMSOLL_SANITIZED_BUILD
    return "env \"ASAN_OPTIONS=${ASAN_OPTIONS}:hard_rss_limit_mb=" + std::to_string(bytes >> 20) +
           "\"";
#else
    return "prlimit --as=" + std::to_string(bytes) + " --";
#endif
}

/// `environment` is prepended to the command line (e.g. "OCL_ICD_VENDORS=/none").
inline CommandOutput runPlimsoll(const std::string& arguments,
                                 const std::string& environment = "") {
    namespace fs = std::filesystem;
    // ctest runs tests as parallel processes: each call gets its own stderr file.
    static int calls = 0;
    const fs::path errFile =
        fs::temp_directory_path() / "plimsoll_tests" /
        ("stderr_" + std::to_string(::getpid()) + "_" + std::to_string(calls++) + ".txt");
    fs::create_directories(errFile.parent_path());
    const std::string command = environment + " '" + plimsollExecutable().string() + "' " +
                                arguments + " 2>'" + errFile.string() + "'";
    CommandOutput result;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
        result.out.append(buffer.data(), n);
    const int status = ::pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    {
        std::ifstream err(errFile);
        result.err.assign(std::istreambuf_iterator<char>(err), {});
    }
    fs::remove(errFile);
    return result;
}

}  // namespace plimsoll::test
