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

// Vertex properties "name[0]" .. "name[k-1]" (how we write a k-component field to PLY) become
// one field again.
void regroup_component_fields(Surface& surface) {
    std::vector<Field> grouped;
    for (size_t i = 0; i < surface.fields.size();) {
        const std::string& name = surface.fields[i].name;
        const std::string base = name.size() > 3 && name.substr(name.size() - 3) == "[0]"
                                     ? name.substr(0, name.size() - 3)
                                     : std::string();
        size_t k = 0;
        if (!base.empty())
            while (i + k < surface.fields.size() && surface.fields[i + k].components == 1 &&
                   surface.fields[i + k].name == base + "[" + std::to_string(k) + "]")
                ++k;
        if (k < 2) {
            grouped.push_back(std::move(surface.fields[i++]));
            continue;
        }
        Field field;
        field.name = base;
        field.components = int(k);
        field.kind = surface.fields[i].kind == FieldKind::Label ? FieldKind::Label
                                                                : field_kind(base, int(k), false);
        const size_t n = surface.vertex_count();
        field.values.resize(n * k);
        for (size_t c = 0; c < k; ++c)
            for (size_t v = 0; v < n; ++v)
                field.values[v * k + c] = surface.fields[i + c].values[v];
        grouped.push_back(std::move(field));
        i += k;
    }
    surface.fields = std::move(grouped);
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
