// The server's log (spdlog, to stderr): text lines, or with --log-format json one JSON object per
// line ({"time", "level", "message"}) for a log collector. Client-chosen strings are escaped
// where they are logged (log_text.h), so neither format can be forged by a client.
#pragma once

#include "config.h"

namespace ddsimp::server {

void setup_logging(const Config& config);

} // namespace ddsimp::server
