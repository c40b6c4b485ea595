#include "sessions.h"

#include <algorithm>

namespace ddsimp::server {

v1::SessionState Session::state(const std::string& cause, uint64_t changed_by) const {
    v1::SessionState s;
    s.set_name(name);
    s.set_version(version);
    for (const v1::Member& m : members) *s.add_members() = m;
    s.set_leader(leader);
    *s.mutable_view() = view;
    s.set_cause(cause);
    s.set_changed_by(changed_by);
    return s;
}

bool Session::has(uint64_t client) const {
    return std::any_of(members.begin(), members.end(),
                       [&](const v1::Member& m) { return m.client_id() == client; });
}

Session* Sessions::join(const std::string& scope, const std::string& name, const v1::Member& member,
                        bool* created) {
    *created = false;
    auto it = sessions_.find(scope);
    if (it == sessions_.end()) {
        if (sessions_.size() >= max_) return nullptr;
        Session s;
        s.name = name;
        s.scope = scope;
        it = sessions_.emplace(scope, std::move(s)).first;
        it->second.leader = member.client_id();
        it->second.view.set_keep(1.0f);
        it->second.view.set_alpha(0.5f);
        *created = true;
    }
    Session& s = it->second;
    if (!s.has(member.client_id())) {
        s.members.push_back(member);
        ++s.version;
    }
    return &s;
}

Session* Sessions::leave(const std::string& scope, uint64_t client, bool* leader_changed) {
    *leader_changed = false;
    auto it = sessions_.find(scope);
    if (it == sessions_.end()) return nullptr;
    Session& s = it->second;
    auto& m = s.members;
    m.erase(std::remove_if(m.begin(), m.end(),
                           [&](const v1::Member& x) { return x.client_id() == client; }),
            m.end());
    if (m.empty()) {
        sessions_.erase(it);
        return nullptr;
    }
    if (s.leader == client) {
        s.leader = m.front().client_id();
        *leader_changed = true;
    }
    ++s.version;
    return &s;
}

Session* Sessions::find(const std::string& scope) {
    auto it = sessions_.find(scope);
    return it == sessions_.end() ? nullptr : &it->second;
}

} // namespace ddsimp::server
