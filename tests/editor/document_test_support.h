// What the editor's document tests share: opening a project and running a command, each
// failing the test (with the document's message) when it does not work.
#pragma once

#include "document/document.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

namespace plimsoll::test {

inline std::unique_ptr<editor::Document> openOrFail(const std::filesystem::path& path) {
    Result<std::unique_ptr<editor::Document>> d = editor::Document::open(path);
    EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
    return d.ok() ? std::move(d).value() : nullptr;
}

inline void executeOrFail(editor::Document& d, Result<std::unique_ptr<editor::Command>> command) {
    ASSERT_TRUE(command.ok()) << command.error().message;
    Status s = d.execute(std::move(command).value());
    ASSERT_TRUE(s.ok()) << s.error().message;
}

}  // namespace plimsoll::test
