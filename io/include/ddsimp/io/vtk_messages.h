// Turns VTK's printed error messages into text we can put in one error line.
#pragma once

#include <memory>
#include <string>

namespace ddsimp::io {

// While alive, VTK's errors and warnings are collected instead of printed to stderr (VTK readers
// report problems only by printing). The first capture also switches VTK's logger output to
// stderr off for good: ddsimp_io reports VTK's errors in its exceptions instead. Not
// thread-safe: VTK's output window is process-global.
class VtkMessageCapture {
public:
    VtkMessageCapture();
    ~VtkMessageCapture();
    VtkMessageCapture(const VtkMessageCapture&) = delete;
    VtkMessageCapture& operator=(const VtkMessageCapture&) = delete;

    bool has_error() const;
    // The first error, without VTK's "ERROR: In file, line" prefix, on one line.
    std::string first_error() const;
    void clear();

private:
    struct State;
    std::unique_ptr<State> state_;
};

} // namespace ddsimp::io
