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

/// `environment` is prepended to the command line (e.g. "OCL_ICD_VENDORS=/none").
inline CommandOutput runPlimsoll(const std::string& arguments, const std::string& environment = "") {
    namespace fs = std::filesystem;
    // ctest runs tests as parallel processes: each call gets its own stderr file.
    static int calls = 0;
    const fs::path errFile = fs::temp_directory_path() / "plimsoll_tests" /
                             ("stderr_" + std::to_string(::getpid()) + "_" +
                              std::to_string(calls++) + ".txt");
    fs::create_directories(errFile.parent_path());
    const std::string command = environment + " '" + PLIMSOLL_EXECUTABLE + "' " + arguments +
                                " 2>'" + errFile.string() + "'";
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
