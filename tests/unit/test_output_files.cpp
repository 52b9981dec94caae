// Output paths (atomic_file.h): each kind of path a user can name as an output keeps what it is.
// A regular file is replaced whole only on commit (and left as it was without one), a symbolic link
// stays a link and its target is replaced, a device (/dev/null) and a FIFO are streamed to and stay
// what they are, a directory is refused at once, write errors (/dev/full) are errors with the
// system's reason, an output that is an input or another output is refused, and no temporary is
// left behind on any path.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "atomic_file.h"
#include "errors.h"

using namespace corebox;
namespace fs = std::filesystem;

namespace {

class OutputFiles : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("corebox_output_files_" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    static std::string read(const std::string& p) {
        std::ifstream in(p);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    static void write(const std::string& p, const std::string& text) { std::ofstream(p) << text; }
    // Files in the directory whose name holds ".tmp-".
    int temporaries() const {
        int n = 0;
        for (const auto& e : fs::directory_iterator(m_dir)) n += e.path().filename().string().find(".tmp-") != std::string::npos;
        return n;
    }

    fs::path m_dir;
};

std::string inputErrorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_F(OutputFiles, ARegularFileIsReplacedOnlyOnCommit) {
    const std::string p = path("obs.csv");
    write(p, "old\n");
    {
        AtomicFile f(p);
        f.stream() << "row 1\n";
        f.flush();
        EXPECT_EQ(read(p), "old\n") << "the old file stays until commit";
        EXPECT_EQ(temporaries(), 1) << "rows go to the temporary as they are written";
        f.commit();
    }
    EXPECT_EQ(read(p), "row 1\n");
    {
        AtomicFile f(p);
        f.stream() << "half";
    }  // destroyed without commit: an error path
    EXPECT_EQ(read(p), "row 1\n");
    EXPECT_EQ(temporaries(), 0);
}

TEST_F(OutputFiles, ASymbolicLinkStaysALinkAndItsTargetIsReplaced) {
    fs::create_directories(m_dir / "real");
    write(path("real/target.csv"), "old\n");
    fs::create_symlink("real/target.csv", m_dir / "link.csv");
    {
        AtomicFile f(path("link.csv"));
        f.stream() << "new\n";
        f.commit();
    }
    EXPECT_TRUE(fs::is_symlink(m_dir / "link.csv"));
    EXPECT_EQ(read(path("real/target.csv")), "new\n");
    // A dangling link: the file it names is created, the link kept.
    fs::create_symlink("real/later.csv", m_dir / "dangling.csv");
    writeOutputFile(path("dangling.csv"), "made\n");
    EXPECT_TRUE(fs::is_symlink(m_dir / "dangling.csv"));
    EXPECT_EQ(read(path("real/later.csv")), "made\n");
    EXPECT_EQ(temporaries(), 0);
}

TEST_F(OutputFiles, DevicesAreStreamedToAndStayDevices) {
    {
        AtomicFile f("/dev/null");
        f.stream() << "rows\n";
        f.commit();
    }
    struct stat st;
    ASSERT_EQ(::stat("/dev/null", &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode));
    EXPECT_EQ(inspectOutput("/dev/null").kind, OutputKind::Stream);
}

TEST_F(OutputFiles, AFifoIsStreamedToAndStaysAFifo) {
    const std::string p = path("pipe");
    ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] { received = read(p); });
    {
        AtomicFile f(p);
        f.stream() << "a,b\n1,2\n";
        f.commit();
    }
    reader.join();
    EXPECT_EQ(received, "a,b\n1,2\n");
    struct stat st;
    ASSERT_EQ(::lstat(p.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

TEST_F(OutputFiles, ADirectoryIsRefusedAtOnce) {
    EXPECT_NE(inputErrorOf([&] { checkWritable(m_dir.string(), "--observables"); }).find("is a directory"), std::string::npos);
    EXPECT_NE(inputErrorOf([&] { AtomicFile f(m_dir.string()); }).find("is a directory"), std::string::npos);
    fs::create_symlink(m_dir, m_dir / "dirlink");
    EXPECT_NE(inputErrorOf([&] { checkWritable(path("dirlink"), "--state-out"); }).find("--state-out"), std::string::npos);
    EXPECT_NE(inputErrorOf([&] { checkWritable(path("missing/obs.csv"), "--observables"); }).find("--observables: cannot write"),
              std::string::npos);
}

TEST_F(OutputFiles, WriteErrorsAreErrorsWithTheReason) {
    ASSERT_TRUE(fs::exists("/dev/full"));
    const std::string onFlush = inputErrorOf([] {
        AtomicFile f("/dev/full");
        f.stream() << "row\n";
        f.flush();
    });
    EXPECT_NE(onFlush.find("No space left on device"), std::string::npos) << onFlush;
    const std::string onCommit = inputErrorOf([] {
        AtomicFile f("/dev/full");
        f.stream() << "row\n";
        f.commit();
    });
    EXPECT_NE(onCommit.find("cannot write '/dev/full'"), std::string::npos) << onCommit;
}

TEST_F(OutputFiles, AnOutputThatIsAnInputOrAnotherOutputIsRefused) {
    const std::string scene = path("scene.toml");
    write(scene, "[box]\n");
    fs::create_symlink("scene.toml", m_dir / "alias.toml");
    const std::vector<NamedPath> inputs{{"scene", scene}, {"--script", ""}};
    const std::string same = inputErrorOf([&] { checkDistinctPaths(inputs, {{"--observables", path("alias.toml")}}); });
    EXPECT_NE(same.find("is this run's scene"), std::string::npos) << same;
    EXPECT_EQ(read(scene), "[box]\n");
    const std::string twice =
        inputErrorOf([&] { checkDistinctPaths(inputs, {{"--observables", path("o.csv")}, {"--state-out", path("./x/../o.csv")}}); });
    EXPECT_NE(twice.find("both name"), std::string::npos) << twice;
    EXPECT_EQ(inputErrorOf([&] {
                  checkDistinctPaths(inputs, {{"--observables", "/dev/null"}, {"--state-out", "/dev/null"}, {"--screenshot", ""}});
              }),
              "")
        << "a device may be shared";
    EXPECT_EQ(inputErrorOf([&] { checkDistinctPaths(inputs, {{"--observables", path("o.csv")}, {"--state-out", path("s.csv")}}); }),
              "");
}
