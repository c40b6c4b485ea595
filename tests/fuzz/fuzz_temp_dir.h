// A directory of this fuzz process's own, removed at exit: in /dev/shm when there is one (the
// targets write a file per input), else in TMPDIR.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace ddsimp::fuzz {

inline const std::string& temp_dir() {
    struct Dir {
        std::string path;
        Dir() {
            namespace fs = std::filesystem;
            const fs::path base =
                fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
            path = (base / ("ddsimp-fuzz-" + std::to_string(getpid()))).string();
            fs::create_directories(path);
        }
        ~Dir() {
            std::error_code ec;
            std::filesystem::remove_all(path, ec);
        }
    };
    static const Dir dir;
    return dir.path;
}

} // namespace ddsimp::fuzz
