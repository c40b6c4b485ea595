// The frame decoders: FrameDecoder fed the input in pieces of fuzz-chosen sizes (as a TCP stream
// arrives), decode_single_frame on the rest (as a WebSocket message), and every frame's payload
// parsed as the message its type names. A frame that comes out must be exactly the bytes that
// went in; anything bad must be a FrameError.
#include "fuzz_check.h"
#include "fuzz_input.h"
#include "fuzz_messages.h"

#include "ddsimp/protocol/frame.h"

namespace {

using namespace ddsimp::protocol;

// The payload parses as its type's message, or is a FrameError.
void parse(const Frame& frame) {
    try {
        ddsimp::fuzz::parse_frame(frame);
    } catch (const FrameError&) {
    }
}

// The header and payload of `frame` as they travel.
std::string bytes_of(const Frame& frame) {
    std::string out(kHeaderBytes, '\0');
    write_header(reinterpret_cast<unsigned char*>(out.data()), frame.type,
                 uint32_t(frame.payload.size()));
    return out + frame.payload;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ddsimp::fuzz::FuzzInput in(data, size);
    const size_t limits[] = {0, 16, 4096, kDefaultMaxFrameBytes};
    const size_t max_frame_bytes = limits[in.take<uint8_t>() % 4];
    const size_t piece = 1 + in.take<uint8_t>();
    const std::string_view stream = in.rest();

    FrameDecoder decoder(max_frame_bytes);
    std::string decoded; // every frame that came out, as bytes
    try {
        for (size_t at = 0; at < stream.size(); at += piece) {
            decoder.feed(stream.substr(at, piece));
            while (std::optional<Frame> frame = decoder.next()) {
                FUZZ_CHECK(frame->payload.size() <= max_frame_bytes);
                decoded += bytes_of(*frame);
                parse(*frame);
            }
        }
        FUZZ_CHECK(decoded.size() + decoder.buffered() == stream.size());
        FUZZ_CHECK(decoded == stream.substr(0, decoded.size()));
    } catch (const FrameError&) {
        FUZZ_CHECK(decoded == stream.substr(0, decoded.size()));
    }

    try {
        const Frame frame = decode_single_frame(stream, max_frame_bytes);
        FUZZ_CHECK(bytes_of(frame) == stream);
        parse(frame);
    } catch (const FrameError&) {
    }
    return 0;
}
