// ddsimp-server's native protocol from the first byte: the input (after one byte of options) is
// what a client sends on a fresh connection, handshake included, cut into frames as
// StreamTransport cuts them and handled by the Connection and Service. Nothing a client sends
// may crash the server, make it write a malformed frame or lose track of its resources.
#include "fake_server.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ddsimp::fuzz::FuzzInput in(data, size);
    const uint8_t options = in.take<uint8_t>();
    ddsimp::fuzz::FakeServer server(/*token=*/options & 1);
    // Either the server acts on each frame before the next arrives, or a burst arrives at once.
    server.deliver_stream(in.rest(), /*step=*/options & 2);
    return 0;
}
