// Inputs kept in fuzz/regressions/ (what the fuzzers once crashed on, and hand-made inputs at
// the readers' limits) go through the fuzzing harnesses' own functions in the ordinary suite:
// each read ends in a scene or mesh, or in SceneError / MeshFileError, never in another
// exception, a crash or a read without end (a scene naming /dev/zero as its mesh file).

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "fuzz/fuzz_inputs.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

template <class Read>
void replay_folder(const std::string& folder, Read read) {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(fs::path("fuzz/regressions") / folder)) {
        SCOPED_TRACE(entry.path().string());
        const std::string bytes = test::read_text(entry.path());
        EXPECT_NO_THROW(read(bytes));
        ++count;
    }
    EXPECT_GE(count, 4) << "fuzz/regressions/" << folder << " lost its inputs";
}

TEST(FuzzRegressions, SceneReaderInputsEndInASceneOrASceneError) {
    replay_folder("scene_reader", [](const std::string& bytes) {
        fuzz::read_scene_input(bytes, "scenes/fuzz-input.toml");
    });
}

TEST(FuzzRegressions, GmshReaderInputsEndInAMeshOrAMeshFileError) {
    replay_folder("gmsh_reader", [](const std::string& bytes) { fuzz::read_gmsh_input(bytes); });
}

// The device case directly: the reader refuses it with a message instead of reading forever.
TEST(FuzzRegressions, MeshFileThatIsNoRegularFileIsRefused) {
    for (const char* path : {"/dev/zero", "scenes/meshes"}) {
        try {
            parse_gmsh_file(path);
            ADD_FAILURE() << path << " was read";
        } catch (const MeshFileError& e) {
            EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos)
                << e.what();
        }
    }
}

} // namespace
} // namespace ifsim::io
