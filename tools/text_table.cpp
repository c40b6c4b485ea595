#include "text_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ddsimp::cli {

namespace {

// Characters in UTF-8 text: every byte that does not continue a sequence.
size_t display_width(const std::string& s) {
    return size_t(std::count_if(
        s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

} // namespace

void TextTable::add_row(std::vector<std::string> cells) {
    if (cells.size() > columns_.size())
        throw std::invalid_argument("a table row of " + std::to_string(cells.size()) +
                                    " cells for " + std::to_string(columns_.size()) + " columns");
    cells.resize(columns_.size());
    rows_.push_back(std::move(cells));
}

std::string TextTable::render(const std::string& indent) const {
    std::vector<size_t> width(columns_.size());
    for (size_t c = 0; c < columns_.size(); ++c) {
        width[c] = display_width(columns_[c].title);
        for (const auto& row : rows_) width[c] = std::max(width[c], display_width(row[c]));
    }
    std::string out;
    auto line = [&](auto cell_of) {
        std::string text = indent;
        for (size_t c = 0; c < columns_.size(); ++c) {
            const std::string cell = cell_of(c);
            const std::string pad(width[c] - display_width(cell), ' ');
            if (c > 0) text += "  ";
            text += columns_[c].align == Align::Right ? pad + cell : cell + pad;
        }
        text.erase(text.find_last_not_of(' ') + 1);
        out += text + "\n";
    };
    line([&](size_t c) { return columns_[c].title; });
    line([&](size_t c) { return std::string(width[c], '-'); });
    for (const auto& row : rows_) line([&](size_t c) { return row[c]; });
    return out;
}

std::string table_number(double x) {
    char buffer[32];
    if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15)
        std::snprintf(buffer, sizeof buffer, "%.0f", x);
    else
        std::snprintf(buffer, sizeof buffer, "%.4g", x);
    return buffer;
}

} // namespace ddsimp::cli
