// Shared by the tools tests: where things are, scratch directories, small surfaces.
#pragma once

#include <ddsimp/ddsimp.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

namespace ddsimp::tools_test {

// A reader's notes (io::Notes), one per line: what a failed expectation prints or searches.
inline std::string all(const std::vector<std::string>& notes) {
    std::string out;
    for (const std::string& n : notes) out += n + "\n";
    return out;
}

inline std::string shared_data(const std::string& relative) {
    return std::string(DDSIMP_SHARED_DATA) + "/" + relative;
}
inline std::string sample_surface() {
    return std::string(DDSIMP_SAMPLE_DATA) + "/SurfaceVectors.vtk";
}

// Skips the test if the shared data set is not there (a checkout without ../shared/data).
#define DDSIMP_REQUIRE_SHARED(path)                                                                \
    do {                                                                                           \
        if (!std::filesystem::exists(path)) GTEST_SKIP() << "not found: " << (path);               \
    } while (0)

// A fresh directory per test, removed afterwards.
class ScratchDir {
public:
    ScratchDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = std::filesystem::temp_directory_path() /
                ("ddsimp_tools_" + std::to_string(::getpid()) + "_" + info->test_suite_name() +
                 "_" + info->name());
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() { std::filesystem::remove_all(path_); }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

// Two triangles sharing an edge (a unit square in z = 0), a scalar, a vector and a 2-component
// field, with values that are not round in binary or decimal.
inline Surface square_with_fields() {
    Surface s;
    s.positions = {0.1f, 0.2f, 0.0f, 1.3f, 0.2f, 0.0f, 1.3f, 1.7f, 0.0f, 0.1f, 1.7f, 0.0f};
    s.triangles = {0, 1, 2, 0, 2, 3};
    s.fields.push_back({"Temp", 1, {300.125f, 301.7f, 299.9f, 1.0f / 3.0f}});
    s.fields.push_back({"V", 3, {1, 2, 3, -4, 5.5f, 6, 0.1f, 0.2f, 0.3f, 1e-7f, -2e7f, 3.14159f}});
    s.fields.push_back({"uv", 2, {0, 1, 2, 3, 4, 5, 6, 7}});
    return s;
}

// Three triangles on one edge (0-1): a non-manifold surface OpenMesh's connectivity refuses.
inline Surface fin_of_three() {
    Surface s;
    s.positions = {0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1};
    s.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    return s;
}

} // namespace ddsimp::tools_test
