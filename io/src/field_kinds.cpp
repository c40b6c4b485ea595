#include "field_kinds.h"

#include <algorithm>
#include <cctype>

namespace ddsimp::io {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// "Id", "Ids", "ID" or "IDs" closing a camel-case name ("GlobalNodeId"), or "id"/"ids" as a word
// of its own ("cell_id", "id"); not the end of a word such as "fluid" or "Void".
bool names_an_id(const std::string& name) {
    const std::string low = lower(name);
    const auto before = [&](size_t tail) {
        return name.size() > tail ? static_cast<unsigned char>(name[name.size() - tail - 1]) : 0;
    };
    for (const std::string tail : {"Id", "Ids", "ID", "IDs"})
        if (ends_with(name, tail) && !std::isupper(before(tail.size()))) return true;
    for (const std::string tail : {"id", "ids"})
        if (ends_with(low, tail) && !std::isalnum(before(tail.size()))) return true;
    return false;
}

} // namespace

FieldKind field_kind(const std::string& name, int components, bool integer_type, bool is_normals) {
    const std::string l = lower(name);
    if (is_normals || (components == 3 && (l == "normals" || l == "normal")))
        return FieldKind::Direction;
    if (integer_type || names_an_id(name) || l.find("label") != std::string::npos)
        return FieldKind::Label;
    return FieldKind::Continuous;
}

const char* describe(FieldKind kind) {
    switch (kind) {
    case FieldKind::Continuous:
        return "continuous";
    case FieldKind::Label:
        return "label";
    case FieldKind::Direction:
        return "direction";
    }
    return "unknown";
}

} // namespace ddsimp::io
