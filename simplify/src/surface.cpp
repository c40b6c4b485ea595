#include "ddsimp/ddsimp.h"

namespace ddsimp {

const Field* Surface::find_field(std::string_view name) const {
    for (const Field& field : fields)
        if (field.name == name) return &field;
    return nullptr;
}

const char* describe(StopReason reason) {
    switch (reason) {
    case StopReason::TargetReached: return "target reached";
    case StopReason::WeightBound: return "the lightest remaining element exceeds the weight bound";
    case StopReason::NothingRemovable:
        return "nothing more removable without changing topology or folding a triangle";
    case StopReason::Cancelled: return "cancelled";
    }
    return "unknown";
}

// Placeholders until the real stages land (the lead is writing them).
RepairReport validate(Surface&) { throw std::logic_error("validate: not built yet"); }
Topology analyze_topology(const Surface&) { throw std::logic_error("not built yet"); }
std::vector<float> vertex_curvature(const Surface&) { throw std::logic_error("not built yet"); }
std::vector<float> vertex_gradient(const Surface&, const std::vector<std::string>&) {
    throw std::logic_error("not built yet");
}
Result simplify(const Surface&, const Options&) { throw std::logic_error("not built yet"); }
ProgressiveRecord ProgressiveRecord::build(const Surface&, const Options&) {
    throw std::logic_error("not built yet");
}
Surface ProgressiveRecord::after(size_t) const { throw std::logic_error("not built yet"); }
Surface ProgressiveRecord::level(size_t) const { throw std::logic_error("not built yet"); }
size_t ProgressiveRecord::operations_for(size_t) const { throw std::logic_error("not built yet"); }

} // namespace ddsimp
