// ddsimp-server's configuration: flag > environment (DDSIMP_*) > file (--config) > default.
#include "config.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using ddsimp::server::Config;
using ddsimp::server::parse_config;

// Sets an environment variable for the life of the object.
struct ScopedEnvironment {
    std::string name;
    ScopedEnvironment(std::string n, const char* value) : name(std::move(n)) {
        setenv(name.c_str(), value, 1);
    }
    ~ScopedEnvironment() { unsetenv(name.c_str()); }
};

class ConfigTest : public ::testing::Test {
protected:
    std::filesystem::path file = std::filesystem::temp_directory_path() /
                                 ("ddsimp-config-test-" + std::to_string(getpid()) + ".conf");
    void TearDown() override { std::filesystem::remove(file); }

    void write_file(const std::string& text) { std::ofstream(file) << text; }

    static Config parse(std::vector<std::string> args) {
        args.insert(args.begin(), "ddsimp-server");
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        return parse_config(int(argv.size()), argv.data());
    }
};

TEST_F(ConfigTest, DefaultsWithoutFlagsEnvironmentOrFile) {
    const Config c = parse({});
    EXPECT_EQ(c.port, 7420);
    EXPECT_EQ(c.http_port, 7421);
    EXPECT_EQ(c.log_level, "info");
}

TEST_F(ConfigTest, FileSetsWhatNothingElseSets) {
    write_file("http-port = 9999\nlog-level = debug\n");
    const Config c = parse({"--config", file.string()});
    EXPECT_EQ(c.http_port, 9999);
    EXPECT_EQ(c.log_level, "debug");
}

TEST_F(ConfigTest, EnvironmentBeatsFile) {
    write_file("http-port = 9999\nlog-level = debug\n");
    const ScopedEnvironment env("DDSIMP_HTTP_PORT", "8421");
    const Config c = parse({"--config", file.string()});
    EXPECT_EQ(c.http_port, 8421);
    EXPECT_EQ(c.log_level, "debug") << "a key without a variable still comes from the file";
}

TEST_F(ConfigTest, FlagBeatsEnvironmentAndFile) {
    write_file("http-port = 9999\n");
    const ScopedEnvironment env("DDSIMP_HTTP_PORT", "8421");
    const Config c = parse({"--config", file.string(), "--http-port", "7777"});
    EXPECT_EQ(c.http_port, 7777);
}

TEST_F(ConfigTest, EmptyEnvironmentVariableLeavesTheFileValue) {
    write_file("token = from-file\n");
    const ScopedEnvironment env("DDSIMP_TOKEN", "");
    EXPECT_EQ(parse({"--config", file.string()}).token, "from-file");
}

} // namespace
