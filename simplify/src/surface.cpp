#include "ddsimp/ddsimp.h"

namespace ddsimp {

const Field* Surface::find_field(std::string_view name) const {
    for (const Field& field : fields)
        if (field.name == name) return &field;
    return nullptr;
}

std::vector<std::string> default_gradient_fields(const Surface& surface) {
    std::vector<std::string> names;
    for (const Field& field : surface.fields)
        if (field.kind == FieldKind::Continuous) names.push_back(field.name);
    return names;
}

const char* describe(StopReason reason) {
    switch (reason) {
    case StopReason::TargetReached:
        return "target reached";
    case StopReason::WeightBound:
        return "the lightest remaining element exceeds the weight bound";
    case StopReason::NothingRemovable:
        return "nothing more removable without changing topology or folding a triangle";
    case StopReason::Cancelled:
        return "cancelled";
    }
    return "unknown";
}

} // namespace ddsimp
