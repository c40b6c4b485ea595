// PublishToSession: passes its polygonal input through and uploads it (triangulated, with every
// numeric point-data array as a field) into a ddsimp-server session, so that the session's web
// and VR members see it as soon as it is stored. It stays a member of the session while it
// exists and uploads again whenever its input or its properties change. The output's field data
// says what happened: PublishedSurface (the surface's id, "" if none) and PublishStatus (a
// sentence: where it went, or why it did not).
#ifndef vtkPublishToSession_h
#define vtkPublishToSession_h

#include "ddsimpParaViewFiltersModule.h" // export macro

#include <vtkPolyDataAlgorithm.h>

#include <memory>

class DDSIMPPARAVIEWFILTERS_EXPORT vtkPublishToSession : public vtkPolyDataAlgorithm {
public:
    static vtkPublishToSession* New();
    vtkTypeMacro(vtkPublishToSession,
                 vtkPolyDataAlgorithm) void PrintSelf(ostream& os, vtkIndent indent) override;

    // "HOST:PORT" of the ddsimp-server (its native port, 7420 by default); empty: publish nothing.
    vtkSetStdStringFromCharMacro(Server);
    vtkGetCharFromStdStringMacro(Server);
    // The server's token, if it requires one.
    vtkSetStdStringFromCharMacro(Token);
    vtkGetCharFromStdStringMacro(Token);
    // The session to publish into (created if it does not exist yet) and its key.
    vtkSetStdStringFromCharMacro(Session);
    vtkGetCharFromStdStringMacro(Session);
    vtkSetStdStringFromCharMacro(Key);
    vtkGetCharFromStdStringMacro(Key);
    // The surface's name in the server's lists.
    vtkSetStdStringFromCharMacro(Name);
    vtkGetCharFromStdStringMacro(Name);

protected:
    vtkPublishToSession();
    ~vtkPublishToSession() override;
    int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

    std::string Server;
    std::string Token;
    std::string Session;
    std::string Key;
    std::string Name = "paraview";

private:
    vtkPublishToSession(const vtkPublishToSession&) = delete;
    void operator=(const vtkPublishToSession&) = delete;
    struct Connection; // the client and what it joined
    std::unique_ptr<Connection> Connection_;
};

#endif
