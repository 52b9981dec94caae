// The speed-vs-accuracy panel's lines (study_curves.h) from the committed study of the argon preset
// (docs/results/study_argon_gas_cpu.json, written by `corebox study`): found beside the scene, one
// line per method, precision and adaptivity with the study's finished runs, by cost, every drift
// rate positive, and rk4's drift falling as its cost grows; a file that is not a study is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "errors.h"
#include "scene_io.h"
#include "study_curves.h"

using namespace corebox;
namespace fs = std::filesystem;

TEST(StudyCurves, ReadsTheLinesOfTheArgonStudy) {
    const Scene argon = loadScene(std::string(COREBOX_SOURCE_DIR) + "/assets/argon_gas.toml");
    const std::string found = findStudyFile(argon, "cpu");
    ASSERT_EQ(fs::weakly_canonical(found), fs::weakly_canonical(fs::path(COREBOX_SOURCE_DIR) / "docs" / "results" / "study_argon_gas_cpu.json"));
    const std::vector<AccuracySeries> lines = loadStudyCurves(found);
    ASSERT_GE(lines.size(), 10u);
    const AccuracySeries* rk4 = nullptr;
    for (const AccuracySeries& line : lines) {
        EXPECT_FALSE(line.points.empty()) << line.label;
        EXPECT_EQ(line.faint, line.label.find("fp32") != std::string::npos) << line.label;
        for (size_t k = 1; k < line.points.size(); ++k) EXPECT_GE(line.points[k][0], line.points[k - 1][0]) << line.label << ": by cost";
        for (const auto& p : line.points) EXPECT_GT(p[1], 0) << line.label;
        if (line.label == "rk4 fp64") rk4 = &line;
    }
    ASSERT_NE(rk4, nullptr);
    ASSERT_GE(rk4->points.size(), 3u);
    EXPECT_LT(rk4->points.back()[1], rk4->points.front()[1]) << "rk4 drifts less at a smaller step";
}

TEST(StudyCurves, RefusesAFileThatIsNotAStudy) {
    const fs::path file = fs::temp_directory_path() / ("corebox_not_a_study_" + std::to_string(::getpid()) + ".json");
    std::ofstream(file) << "{\"benchmark\": \"pile\"}";
    EXPECT_THROW(loadStudyCurves(file.string()), InputError);
    fs::remove(file);
    EXPECT_THROW(loadStudyCurves(file.string()), InputError);
}
