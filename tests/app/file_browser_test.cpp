// The file dialog's logic without any UI (app/file_browser.h), the document's modified flag (app/document.h)
// and the script's "mesh" field (io/script_json.h).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>

#include "../core/mesh_fixtures.h"
#include "../io/io_test_support.h"
#include "app/document.h"
#include "app/file_browser.h"
#include "io/script.h"
#include "io/script_json.h"

using namespace sculpt;

namespace {

void touch(const std::string& path, const std::string& text = "x") { std::ofstream(path) << text; }

}  // namespace

TEST_CASE("file browser: folders first, then matching files, each sorted by name case-insensitively", "[app]") {
    test::TempFolder folder("files_test");
    std::filesystem::create_directory(folder.file("Zeta"));
    std::filesystem::create_directory(folder.file("alpha"));
    std::filesystem::create_directory(folder.file(".hidden_folder"));
    touch(folder.file("b.obj"));
    touch(folder.file("A.OBJ"));
    touch(folder.file("c.json"));
    touch(folder.file(".hidden.obj"));
    touch(folder.file("mesh.obj.bak"));
    std::filesystem::create_symlink(folder.file("missing.obj"), folder.file("dangling.obj"));

    const app::FolderListing listing = app::listFolder(folder.path, {".obj"});
    REQUIRE(listing.error.empty());
    std::vector<std::string> names;
    for (const app::FolderEntry& e : listing.entries) names.push_back(e.name + (e.isFolder ? "/" : ""));
    CHECK(names == std::vector<std::string>{"alpha/", "Zeta/", "A.OBJ", "b.obj"});
    CHECK(listing.entries[2].bytes == 1);

    const app::FolderListing all = app::listFolder(folder.path, {}, true);
    CHECK(all.entries.size() == 8);  // hidden ones too; the dangling link is skipped

    const app::FolderListing missing = app::listFolder(folder.file("nope"), {".obj"});
    CHECK_FALSE(missing.error.empty());
    CHECK(missing.entries.empty());
    const app::FolderListing notAFolder = app::listFolder(folder.file("b.obj"), {".obj"});
    CHECK_FALSE(notAFolder.error.empty());
}

TEST_CASE("file browser: paths join, normalise and climb without touching the disk", "[app]") {
    CHECK(app::joinPath("/a/b", "c.obj") == "/a/b/c.obj");
    CHECK(app::joinPath("/a/b", "../c.obj") == "/a/c.obj");
    CHECK(app::joinPath("/a/b", "/x/./y.obj") == "/x/y.obj");
    CHECK(app::joinPath("/a/b", "sub/") == "/a/b/sub");
    CHECK(app::joinPath("/a/b", "~/m.obj").rfind("/m.obj") != std::string::npos);
    CHECK(app::parentFolder("/a/b") == "/a");
    CHECK(app::parentFolder("/a/b/") == "/a");
    CHECK(app::parentFolder("/a") == "/");
    CHECK(app::parentFolder("/") == "/");
    CHECK(app::folderOfPath("/a/b.obj") == "/a");
    CHECK(app::fileNameOfPath("/a/b.obj") == "b.obj");
    CHECK(app::withDefaultExtension("/a/mesh", ".obj", {".obj"}) == "/a/mesh.obj");
    CHECK(app::withDefaultExtension("/a/mesh.OBJ", ".obj", {".obj"}) == "/a/mesh.OBJ");
    CHECK(app::hasExtension("x.Json", {".obj", ".json"}));
    CHECK_FALSE(app::hasExtension(".obj", {".obj"}));  // a name that is only the extension is no mesh
    CHECK_FALSE(app::hasExtension("obj", {".obj"}));
}

TEST_CASE("file browser: save checks ask before replacing and refuse what cannot be written", "[app]") {
    test::TempFolder folder("files_test");
    touch(folder.file("old.obj"));
    std::filesystem::create_directory(folder.file("sub"));
    CHECK(app::checkSavePath(folder.file("new.obj")).verdict == app::SaveVerdict::Write);
    CHECK(app::checkSavePath(folder.file("old.obj")).verdict == app::SaveVerdict::ConfirmReplace);
    CHECK(app::checkSavePath(folder.file("sub")).verdict == app::SaveVerdict::EnterFolder);
    const app::SaveCheck missing = app::checkSavePath(folder.file("nope/new.obj"));
    CHECK(missing.verdict == app::SaveVerdict::Refuse);
    CHECK(missing.error.find("does not exist") != std::string::npos);
    CHECK(app::checkSavePath("").verdict == app::SaveVerdict::Refuse);
    CHECK(app::checkSavePath("/dev/null").verdict == app::SaveVerdict::Refuse);  // not a regular file

    CHECK(app::checkOpenPath(folder.file("old.obj")).ok);
    CHECK(app::checkOpenPath(folder.file("sub")).isFolder);
    CHECK_FALSE(app::checkOpenPath(folder.file("none.obj")).ok);
    CHECK_FALSE(app::checkOpenPath(folder.file("none.obj")).error.empty());
}

TEST_CASE("document: modified follows the applied history, undo back to the saved state is clean", "[app]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    core::Session session;
    REQUIRE(session.setMesh(positions, triangles).ok);
    app::Document document;
    document.saved = app::markHistory(session);
    CHECK_FALSE(app::isModified(document, session));

    std::mt19937 random(7);  // fixed seed: small random drags of random vertices
    std::uniform_int_distribution<int> vertex(0, static_cast<int>(positions.rows()) - 1);
    std::uniform_real_distribution<double> offset(-0.05, 0.05);
    auto randomDrag = [&]() {
        const int v = vertex(random);
        core::OpReport report;
        const Eigen::Vector3d target = session.mesh().positions.row(v).transpose() +
                                       Eigen::Vector3d(offset(random), offset(random), offset(random));
        REQUIRE(session.dragVertex(v, target, report).ok);
        REQUIRE(report.status == core::OpStatus::Applied);
    };
    randomDrag();
    CHECK(app::isModified(document, session));
    randomDrag();
    document.saved = app::markHistory(session);  // "saved" after two drags
    CHECK_FALSE(app::isModified(document, session));
    core::OpReport report;
    REQUIRE(session.undo(report).ok);
    CHECK(app::isModified(document, session));
    REQUIRE(session.redo(report).ok);
    CHECK_FALSE(app::isModified(document, session));  // back to the saved state
    REQUIRE(session.undo(report).ok);
    randomDrag();  // same cursor as when saved, different operation
    CHECK(session.history().cursor() == document.saved.cursor);
    CHECK(app::isModified(document, session));
    randomDrag();
    CHECK(app::isModified(document, session));
}

TEST_CASE("script json: the optional mesh field round-trips and resolves against the script's folder", "[app]") {
    io::Script script;
    REQUIRE(io::parseScript(R"({"mesh": "../meshes/a.obj", "ops": []})", "s.json", script).ok);
    CHECK(script.mesh == "../meshes/a.obj");
    CHECK(io::resolveScriptMesh(script, "/work/sessions/s.json") == "/work/meshes/a.obj");
    io::Script reread;
    REQUIRE(io::parseScript(io::scriptToJson(script), "t.json", reread).ok);
    CHECK(reread.mesh == script.mesh);
    io::Script none;
    REQUIRE(io::parseScript(R"({"ops": []})", "s.json", none).ok);
    CHECK(none.mesh.empty());
    CHECK(io::resolveScriptMesh(none, "/work/s.json").empty());
    CHECK(io::scriptToJson(none).find("\"mesh\"") == std::string::npos);
    io::Script absolute;
    absolute.mesh = "/data/m.obj";
    CHECK(io::resolveScriptMesh(absolute, "/work/s.json") == "/data/m.obj");

    const Status empty = io::parseScript(R"({"mesh": ""})", "s.json", script);
    CHECK_FALSE(empty.ok);
    CHECK(empty.message.find("mesh") != std::string::npos);
    CHECK_FALSE(io::parseScript(R"({"mesh": 3})", "s.json", script).ok);
    CHECK_FALSE(io::parseScript(R"({"meshes": "a.obj"})", "s.json", script).ok);  // still strict

    CHECK(io::scriptRelativeMeshPath("/work/meshes/a.obj", "/work/sessions/s.json") == "../meshes/a.obj");
    CHECK(io::scriptRelativeMeshPath("/work/sessions/a.obj", "/work/sessions/s.json") == "a.obj");
}
