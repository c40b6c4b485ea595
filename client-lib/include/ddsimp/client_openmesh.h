// libddsimp-client with OpenMesh: upload a TriMesh as it is (see ddsimp/openmesh.h for how its
// vertex properties become fields). Kept apart so client.h needs no OpenMesh headers.
#pragma once

#include "ddsimp/client.h"
#include "ddsimp/openmesh.h"

namespace ddsimp {

// Converts the mesh with from_openmesh (float, Vec3f and std::vector<float> vertex properties
// become fields) and uploads it; blocks until the server stored it. Throws like Client::upload.
inline UploadResult upload(Client& client, const TriMesh& mesh, const std::string& name = {},
                           const std::string& session = {}) {
    return client.upload(from_openmesh(mesh), name, session);
}

// The same without waiting.
inline std::future<UploadResult> async_upload(Client& client, const TriMesh& mesh,
                                              const std::string& name = {},
                                              const std::string& session = {}) {
    return client.async_upload(from_openmesh(mesh), name, session);
}

} // namespace ddsimp
