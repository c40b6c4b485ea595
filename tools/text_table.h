// Tables for a person on a terminal: every column as wide as its widest cell, text to the left,
// numbers to the right, two spaces between columns. (--json outputs are for programs.)
#pragma once

#include <string>
#include <vector>

namespace ddsimp::cli {

class TextTable {
public:
    enum class Align { Left, Right };
    struct Column {
        std::string title;
        Align align = Align::Left;
    };

    explicit TextTable(std::vector<Column> columns) : columns_(std::move(columns)) {}

    // One row; missing cells are empty, extra cells are an error (std::invalid_argument).
    void add_row(std::vector<std::string> cells);

    // The titles, a rule of dashes, then the rows; each line starts with `indent` and has no
    // trailing blanks. Widths count characters, not bytes (UTF-8).
    std::string render(const std::string& indent = "") const;

private:
    std::vector<Column> columns_;
    std::vector<std::vector<std::string>> rows_;
};

// A number for a table: %.4g ("0.0123", "1.235e+05"), or an integer with no exponent.
std::string table_number(double x);

} // namespace ddsimp::cli
