// The fuzzers' corpora (tests/fuzz/corpus), replayed in every ordinary test run: each input must end
// in a scene or particle state, or in an InputError with a message, never in another exception.
// A crash the fuzz stage of scripts/test finds is written into the corpus, so it is replayed here
// from then on.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "errors.h"
#include "scene_io.h"
#include "state_csv.h"

using namespace corebox;
namespace fs = std::filesystem;

namespace {

std::string contentsOf(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Replays every file of tests/fuzz/corpus/NAME through `read`; returns how many it read.
template <class Read>
int replay(const std::string& name, Read&& read) {
    int files = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(fs::path(COREBOX_SOURCE_DIR) / "tests/fuzz/corpus" / name)) {
        if (!entry.is_regular_file()) continue;
        ++files;
        const std::string text = contentsOf(entry.path());
        try {
            read(text);
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()), "") << entry.path();
        } catch (const std::exception& e) {
            ADD_FAILURE() << entry.path() << ": " << e.what();
        }
    }
    return files;
}

}  // namespace

TEST(FuzzCorpus, SceneInputsEndInASceneOrAnInputError) {
    const int files = replay("scene", [](const std::string& text) { (void)parseScene(text, "corpus.toml"); });
    EXPECT_GE(files, 8);  // at least the presets
}

TEST(FuzzCorpus, ParticleFileInputsEndInAStateOrAnInputError) {
    const int files = replay("state_csv", [](const std::string& text) {
        std::istringstream in(text);
        (void)parseStateCsv(in, "corpus.csv");
    });
    EXPECT_GE(files, 4);
}
