// PublishToSession (see vtkPublishToSession.h), over libddsimp-client.
#include "vtkPublishToSession.h"

#include "polydata_surface.h"

#include "ddsimp/client.h"

#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>

vtkStandardNewMacro(vtkPublishToSession);

// One connection, kept while the server and token stay the same, and the session it joined.
struct vtkPublishToSession::Connection {
    std::string server, token, session, key;
    ddsimp::Client client;
};

vtkPublishToSession::vtkPublishToSession() = default;
vtkPublishToSession::~vtkPublishToSession() = default;

namespace {

void add_string(vtkFieldData* fd, const char* name, const std::string& value) {
    vtkNew<vtkStringArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    fd->AddArray(a);
}

} // namespace

int vtkPublishToSession::RequestData(vtkInformation*, vtkInformationVector** inputs,
                                     vtkInformationVector* outputs) {
    vtkPolyData* input = vtkPolyData::GetData(inputs[0]);
    vtkPolyData* output = vtkPolyData::GetData(outputs);
    if (!input || !output) return 0;
    output->ShallowCopy(input);
    vtkNew<vtkFieldData> fd;
    fd->ShallowCopy(input->GetFieldData());
    output->SetFieldData(fd);

    if (this->Server.empty() || this->Session.empty()) {
        add_string(fd, "PublishedSurface", "");
        add_string(fd, "PublishStatus", "not published: set Server and Session");
        return 1;
    }
    try {
        ddsimp::ConnectOptions options;
        ddsimp::parse_server_address(this->Server, options);
        options.token = this->Token;
        options.client_name = "ParaView";
        options.kind = ddsimp::ClientKind::Desktop;
        Connection* c = this->Connection_.get();
        if (!c || c->server != this->Server || c->token != this->Token || !c->client.connected()) {
            this->Connection_.reset(); // closes the old connection first
            this->Connection_ = std::make_unique<Connection>();
            c = this->Connection_.get();
            c->client.connect(options);
            c->server = this->Server;
            c->token = this->Token;
        }
        if (c->session != this->Session || c->key != this->Key) {
            if (!c->session.empty()) c->client.leave_session(c->session);
            c->session.clear();
            c->client.join_session(this->Session, this->Key);
            c->session = this->Session;
            c->key = this->Key;
        }
        std::string skipped;
        const ddsimp::Surface surface = ddsimp::paraview::surface_from_polydata(input, skipped);
        if (!skipped.empty()) vtkWarningMacro(<< "not published: " << skipped);
        const ddsimp::UploadResult stored = c->client.upload(surface, this->Name, this->Session);
        add_string(fd, "PublishedSurface", stored.surface);
        add_string(fd, "PublishStatus",
                   "published to " + this->Server + ", session " + this->Session + ": " +
                       std::to_string(stored.triangles) + " triangles");
    } catch (const std::exception& e) { // ClientError, or a bad address (invalid_argument)
        this->Connection_.reset();
        vtkErrorMacro(<< "cannot publish to " << this->Server << ": " << e.what());
        add_string(fd, "PublishedSurface", "");
        add_string(fd, "PublishStatus", std::string("not published: ") + e.what());
    }
    return 1;
}

void vtkPublishToSession::PrintSelf(ostream& os, vtkIndent indent) {
    this->Superclass::PrintSelf(os, indent);
    os << indent << "Server: " << this->Server << "\n"
       << indent << "Session: " << this->Session << "\n"
       << indent << "Name: " << this->Name << "\n";
}
