#pragma once
#include <chrono>
#include <cstdio>
#include <cstdlib>
namespace ddsimp::detail {
inline double& stage_acc(int i) { static double a[16] = {}; return a[i]; }
struct StageTimer {
    std::chrono::steady_clock::time_point t = std::chrono::steady_clock::now();
    void acc(int i) { auto n = std::chrono::steady_clock::now(); stage_acc(i) += std::chrono::duration<double>(n - t).count(); t = n; }
};
inline void stage_print() {
    if (!std::getenv("DDSIMP_STAGES")) return;
    const char* n[16] = {"validate","construct","rank","select+check","stamp+pend","apply-prep","apply","list","after","","","","","","",""};
    for (int i = 0; i < 9; ++i) std::fprintf(stderr, "%-14s %7.3f\n", n[i], stage_acc(i));
}
}
