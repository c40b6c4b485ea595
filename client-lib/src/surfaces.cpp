// Surfaces on the server: uploading one in chunks, listing those the server holds, deleting one.
#include "client_impl.h"

namespace ddsimp {

void Client::Impl::cut_upload_chunk() {
    UploadJob& job = upload_jobs.front();
    const size_t n = std::min(protocol::kDefaultChunkBytes, job.blob->size() - job.offset);
    v1::UploadChunk chunk;
    chunk.set_upload_id(job.id);
    chunk.set_offset(job.offset);
    chunk.set_data(job.blob->data() + job.offset, n);
    out.push_back(protocol::encode_frame(chunk));
    job.offset += n;
    if (job.offset == job.blob->size()) {
        v1::UploadEnd end;
        end.set_upload_id(job.id);
        out.push_back(protocol::encode_frame(end));
        upload_jobs.pop_front();
    }
}

void Client::Impl::on_upload_result(const v1::UploadResult& message) {
    auto u = uploads.find(message.upload_id());
    if (u == uploads.end()) return;
    u->second.set_value(from_wire(message));
    uploads.erase(u);
}

void Client::Impl::on_surface_list(const v1::SurfaceList& message) {
    auto op = std::find_if(control.begin(), control.end(),
                           [](const ControlOp& o) { return o.kind == ControlOp::Kind::List; });
    if (op == control.end()) return;
    std::vector<SurfaceInfo> list;
    for (const v1::SurfaceInfo& s : message.surfaces()) list.push_back(from_wire(s));
    op->list->set_value(std::move(list));
    control.erase(op);
}

void Client::Impl::on_surface_deleted(const v1::SurfaceDeleted& message) {
    auto d = deletes.find(message.delete_id());
    if (d == deletes.end()) return;
    d->second.set_value(message.removed());
    deletes.erase(d);
}

std::future<UploadResult> Client::async_upload(const Surface& surface, const std::string& name,
                                               const std::string& session) {
    // Encoding happens on the caller's thread, so the network thread stays free.
    protocol::EncodedBlob blob;
    try {
        blob = protocol::encode_mesh(surface, v1::RAW);
    } catch (const protocol::BlobError& e) {
        throw ClientError(ErrorCode::InvalidArgument,
                          std::string("the surface cannot be sent: ") + e.what());
    }
    const uint64_t id = impl_->take_id();
    v1::UploadBegin begin;
    begin.set_upload_id(id);
    begin.set_name(name);
    begin.set_vertex_count(blob.layout.vertex_count);
    begin.set_triangle_count(blob.layout.triangle_count);
    for (const protocol::FieldSpec& f : blob.layout.fields)
        protocol::set_field_info(*begin.add_fields(), f);
    begin.set_total_bytes(blob.bytes.size());
    begin.set_session(session);

    auto promise = std::make_shared<std::promise<UploadResult>>();
    auto future = promise->get_future();
    auto bytes = std::make_shared<const std::string>(std::move(blob.bytes));
    impl_->run([impl = impl_.get(), id, begin = std::move(begin), bytes, promise] {
        if (!impl->require_connection(*promise)) return;
        impl->uploads.emplace(id, std::move(*promise));
        impl->send(protocol::encode_frame(begin));
        if (bytes->empty()) {
            v1::UploadEnd end;
            end.set_upload_id(id);
            impl->send(protocol::encode_frame(end));
        } else {
            impl->upload_jobs.push_back({id, bytes, 0});
            impl->write_next();
        }
    });
    return future;
}

UploadResult Client::upload(const Surface& surface, const std::string& name,
                            const std::string& session) {
    impl_->require_other_thread("upload");
    auto future = async_upload(surface, name, session);
    return impl_->wait(future, "upload", false);
}

std::future<std::vector<SurfaceInfo>> Client::async_list_surfaces() {
    auto promise = std::make_shared<std::promise<std::vector<SurfaceInfo>>>();
    auto future = promise->get_future();
    impl_->run([impl = impl_.get(), promise] {
        if (!impl->require_connection(*promise)) return;
        impl->control.push_back({ControlOp::Kind::List, {}, promise, nullptr});
        impl->send(protocol::encode_frame(v1::ListSurfaces{}));
    });
    return future;
}

std::vector<SurfaceInfo> Client::list_surfaces() {
    auto future = async_list_surfaces();
    return impl_->wait(future, "list_surfaces", true);
}

std::future<bool> Client::async_delete_surface(const std::string& surface) {
    auto promise = std::make_shared<std::promise<bool>>();
    auto future = promise->get_future();
    impl_->run([impl = impl_.get(), id = impl_->take_id(), surface, promise] {
        if (!impl->require_connection(*promise)) return;
        if (!impl->capability("surface-delete"))
            return promise->set_exception(std::make_exception_ptr(
                ClientError(ErrorCode::Unavailable, "the server cannot delete surfaces (it has "
                                                    "no capability \"surface-delete\")")));
        v1::DeleteSurface message;
        message.set_delete_id(id);
        message.set_surface(surface);
        impl->deletes.emplace(id, std::move(*promise));
        impl->send(protocol::encode_frame(message));
    });
    return future;
}

bool Client::delete_surface(const std::string& surface) {
    auto future = async_delete_surface(surface);
    return impl_->wait(future, "delete_surface", false);
}

} // namespace ddsimp
