// Saves lose nothing and stay inside the project's folder: an autosave is kept until the save
// that replaces it succeeds (and another session's is never removed), a recovered autosave
// saves to the project it lies beside, a map read from outside the folder is saved into it
// (the file it came from untouched), and a Save As interrupted at any step keeps every file.
#include "test_support.h"
#include "editor/document_test_support.h"

#include "document/command.h"
#include "document/document.h"

#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/project/project.h"
#include "plimsoll/surface/painted_map.h"

#include "io/test_hooks.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>

namespace plimsoll::editor {
namespace test_document_saves {
namespace {

namespace fs = std::filesystem;
using test::executeOrFail;
using test::openOrFail;

/// The box asset with its permeability map at `map` (relative to the project's folder).
fs::path writeProject(const fs::path& dir, const std::string& map = "perm.png") {
    const fs::path path = dir / "box.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "box", "mesh": ")"
        << test::assetPath("box.obj").string() << R"(", "texture_size": 16, "permeability_map": ")"
        << map << R"(", "material": {"density": 500}}]})";
    EXPECT_TRUE(savePaintedMap(PaintedMap{16, 16, std::vector<float>(256, 0.25f)}, dir / map).ok());
    return path;
}

void edit(Document& d, double drag) {
    executeOrFail(d, makeSetPropertyCommand(d, "/bodies/0/drag_coefficient", drag));
}

TEST(DocumentSaves, AFailedSaveAsKeepsTheAutosaveAndTheDocument) {
    const fs::path dir = test::freshFolder("document_saves", "save_as_fails");
    const fs::path path = writeProject(dir);
    auto d = openOrFail(path);
    edit(*d, 0.7);
    ASSERT_TRUE(d->autosave().ok());
    const fs::path autosave = d->autosavePath();
    ASSERT_TRUE(fs::exists(autosave));
    for (const fs::path target :
         {fs::path("/proc/plimsoll/elsewhere.plim.json"), fs::path("/proc/version")}) {
        SCOPED_TRACE(target.string());
        EXPECT_FALSE(d->saveAs(target, true).ok());
        EXPECT_TRUE(fs::exists(autosave)) << "the autosave of the unsaved edits is gone";
        EXPECT_EQ(d->path(), path);
        EXPECT_TRUE(d->dirty());
    }
    // A Save As that succeeds replaces it.
    ASSERT_TRUE(d->saveAs(dir / "copy.plim.json").ok());
    EXPECT_FALSE(fs::exists(autosave));
    EXPECT_EQ(loadProject(dir / "copy.plim.json")->bodies[0].dragCoefficient, 0.7);
}

TEST(DocumentSaves, ASaveKeepsTheAutosaveAnotherSessionLeft) {
    const fs::path dir = test::freshFolder("document_saves", "crashed");
    const fs::path path = writeProject(dir);
    {
        auto crashed = openOrFail(path);
        edit(*crashed, 0.9);
        ASSERT_TRUE(crashed->autosave().ok());
    }  // the session ends without a save or a discard: a crash
    const fs::path autosave = Document::autosavePathFor(path);
    const std::string kept = test::readFile(autosave);
    auto d = openOrFail(path);  // `edit --script` opens and saves the same way
    edit(*d, 0.3);
    ASSERT_TRUE(d->save().ok());
    ASSERT_TRUE(fs::exists(autosave)) << "the crashed session's edits are lost";
    EXPECT_EQ(test::readFile(autosave), kept);
    // Recovering it and saving replaces it.
    Result<std::unique_ptr<Document>> recovered = Document::recover(autosave);
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    ASSERT_TRUE((*recovered)->save().ok());
    EXPECT_FALSE(fs::exists(autosave));
    EXPECT_EQ(loadProject(path)->bodies[0].dragCoefficient, 0.9);
}

TEST(DocumentSaves, ARecoveredAutosaveSavesToTheProjectItLiesBeside) {
    const fs::path dir = test::freshFolder("document_saves", "recover");
    fs::create_directories(dir / "mine");
    const fs::path path = writeProject(dir / "mine");
    fs::create_directories(dir / "theirs");
    auto d = openOrFail(path);
    edit(*d, 0.6);
    ASSERT_TRUE(d->autosave().ok());
    // The autosave names another project and folder inside: edited, or carried over.
    const fs::path autosave = d->autosavePath();
    std::string text = test::readFile(autosave);
    for (const std::string& from : {path.string(), path.parent_path().string()}) {
        for (std::size_t at = text.find(from); at != std::string::npos;
             at = text.find(from, at + 1))
            text.replace(at, from.size(),
                         from == path.string() ? (dir / "theirs" / "victim.plim.json").string()
                                               : (dir / "theirs").string());
    }
    std::ofstream(autosave, std::ios::trunc) << text;
    Result<std::unique_ptr<Document>> recovered = Document::recover(autosave);
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    EXPECT_EQ((*recovered)->path(), fs::absolute(path).lexically_normal());
    ASSERT_TRUE((*recovered)->save().ok());
    EXPECT_FALSE(fs::exists(dir / "theirs" / "victim.plim.json"));
    EXPECT_TRUE(fs::is_empty(dir / "theirs"));
    EXPECT_EQ(loadProject(path)->bodies[0].dragCoefficient, 0.6);
}

TEST(DocumentSaves, AMapFromOutsideTheFolderIsSavedIntoItAndTheSourceIsUntouched) {
    const fs::path dir = test::freshFolder("document_saves", "outside");
    fs::create_directories(dir / "photos");
    fs::create_directories(dir / "project");
    ASSERT_TRUE(savePaintedMap(PaintedMap{16, 16, std::vector<float>(256, 0.25f)},
                               dir / "photos" / "photo.png")
                    .ok());
    const std::string photo = test::readFile(dir / "photos" / "photo.png");
    for (const std::string& map :
         {std::string("../photos/photo.png"), (dir / "photos" / "photo.png").string()}) {
        SCOPED_TRACE(map);
        const fs::path path = dir / "project" / "box.plim.json";
        std::ofstream(path, std::ios::trunc)
            << R"({"schema_version": 1, "name": "box", "bodies": [{"name": "box", "mesh": ")"
            << test::assetPath("box.obj").string()
            << R"(", "texture_size": 16, "permeability_map": ")" << map
            << R"(", "material": {"density": 500}}]})";
        auto d = openOrFail(path);
        ASSERT_NE(d->map(0, MapChannel::Permeability), nullptr);
        executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Permeability, 0.75));
        ASSERT_TRUE(d->save().ok());
        EXPECT_EQ(test::readFile(dir / "photos" / "photo.png"), photo)
            << "the source was overwritten";
        Result<Project> saved = loadProject(path);
        ASSERT_TRUE(saved.ok()) << saved.error().message;
        const std::string now = saved->bodies[0].permeabilityMap;
        EXPECT_FALSE(fs::path(now).is_absolute()) << now;
        EXPECT_NE(*fs::path(now).begin(), "..") << now;
        EXPECT_NEAR(loadPaintedMap(dir / "project" / now)->values[0], 0.75f, 1e-4);
        fs::remove_all(dir / "project" / "maps");
    }
}

/// Every regular file under `dir` (relative path -> bytes).
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        if (entry.is_regular_file())
            files[fs::relative(entry.path(), dir).generic_string()] = test::readFile(entry.path());
    }
    return files;
}

TEST(DocumentSaves, ASaveAsInterruptedAtAnyStepKeepsEveryFileAndTheAutosave) {
    const fs::path dir = test::freshFolder("document_saves", "save_as_steps");
    const fs::path path = writeProject(dir);
    auto d = openOrFail(path);
    executeOrFail(*d, makeFillAllCommand(*d, 0, MapChannel::Permeability, 0.5));
    ASSERT_TRUE(d->autosave().ok());
    const std::map<std::string, std::string> before = snapshot(dir);
    int k = 1;
    for (; k < 50; ++k) {
        failFileStepForTesting(k);
        const Status s = d->saveAs(dir / "sub" / "moved.plim.json");
        failFileStepForTesting(0);
        if (s.ok()) break;
        SCOPED_TRACE("interrupted at step " + std::to_string(k));
        EXPECT_EQ(snapshot(dir), before);
        EXPECT_EQ(d->path(), path);
    }
    EXPECT_GE(k, 4);  // map and project written, the journal, renames
    EXPECT_FALSE(fs::exists(Document::autosavePathFor(path)));
    EXPECT_NEAR(loadPaintedMap(dir / "sub" / "perm.png")->values[0], 0.5f, 1e-4);
}

}  // namespace
}  // namespace test_document_saves
}  // namespace plimsoll::editor
