#include "ddsimp/io/vtk_messages.h"

#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>

#include <vector>

namespace ddsimp::io {

namespace {

// VTK formats errors as "ERROR: In <file>, line <n>\n<class> (<address>): <message>\n\n";
// keep only the message, on one line.
std::string clean_message(const std::string& text) {
    std::string message = text;
    const size_t object_end = message.find("): ");
    if (object_end != std::string::npos) message = message.substr(object_end + 3);
    for (char& c : message)
        if (c == '\n' || c == '\r') c = ' ';
    while (!message.empty() && (message.back() == ' ' || message.back() == '.')) message.pop_back();
    return message;
}

class CollectingOutputWindow : public vtkOutputWindow {
public:
    static CollectingOutputWindow* New();
    vtkTypeMacro(CollectingOutputWindow, vtkOutputWindow)

        void DisplayText(const char*) override {}
    void DisplayErrorText(const char* text) override { errors.push_back(clean_message(text)); }
    void DisplayWarningText(const char*) override {}
    // VTK's legacy reader only warns when an ASCII array ends before its declared size, and
    // leaves the rest of the array uninitialised: that is an error here.
    void DisplayGenericWarningText(const char* text) override {
        if (std::string(text).find("Possible mismatch of datasize") != std::string::npos)
            errors.push_back("the file ends, or has a word that is not a number, before the "
                             "values it declares");
    }
    void DisplayDebugText(const char*) override {}

    std::vector<std::string> errors;
};
vtkStandardNewMacro(CollectingOutputWindow)

} // namespace

struct VtkMessageCapture::State {
    vtkSmartPointer<vtkOutputWindow> previous;
    vtkSmartPointer<CollectingOutputWindow> window;
};

VtkMessageCapture::VtkMessageCapture() : state_(std::make_unique<State>()) {
    // VTK 9 logs every error through vtkLogger before the output window sees it.
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
    state_->previous = vtkOutputWindow::GetInstance();
    state_->window = vtkSmartPointer<CollectingOutputWindow>::New();
    vtkOutputWindow::SetInstance(state_->window);
}

VtkMessageCapture::~VtkMessageCapture() {
    vtkOutputWindow::SetInstance(state_->previous);
}

bool VtkMessageCapture::has_error() const {
    return !state_->window->errors.empty();
}

std::string VtkMessageCapture::first_error() const {
    return state_->window->errors.empty() ? std::string() : state_->window->errors.front();
}

void VtkMessageCapture::clear() {
    state_->window->errors.clear();
}

} // namespace ddsimp::io
