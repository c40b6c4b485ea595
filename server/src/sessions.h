// Collaborative sessions, as in COVISE: a name, members in the order they joined, a leader and
// the view they share. Server-authoritative; every change bumps the version. A session is found
// by its scope (surface_store.h: the hash of its name and key), so sessions of the same name with
// different keys are different sessions. Network thread only.
#pragma once

#include "ddsimp/v1/ddsimp.pb.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ddsimp::server {

struct Session {
    std::string name;
    std::string scope; // session_scope(name, key)
    uint64_t version = 0;
    std::vector<v1::Member> members; // in joining order
    uint64_t leader = 0;
    v1::View view;
    uint64_t view_version = 0; // changes of what the mesh depends on (not of members or field)

    v1::SessionState state(const std::string& cause, uint64_t changed_by) const;
    bool has(uint64_t client) const;
};

class Sessions {
public:
    explicit Sessions(size_t max_sessions) : max_(max_sessions) {}

    // Joins (creating the session if needed; its first member leads). nullptr if the session
    // limit is reached. Joining twice is a no-op that still returns the session.
    Session* join(const std::string& scope, const std::string& name, const v1::Member& member,
                  bool* created);
    // Removes the member; passes the lead to the longest-present member if it led; deletes an
    // empty session. Returns the session (nullptr if deleted or unknown) and whether the lead
    // changed.
    Session* leave(const std::string& scope, uint64_t client, bool* leader_changed);
    Session* find(const std::string& scope);
    size_t size() const { return sessions_.size(); }

private:
    size_t max_;
    std::map<std::string, Session> sessions_; // by scope
};

} // namespace ddsimp::server
