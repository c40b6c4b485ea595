// The tokens the server accepts: --token, and one per user in --tokens-file. A client is known by
// the name of the token it presented; the quotas on stored surfaces and uploads (quotas.h) are
// per token name.
#pragma once

#include "config.h"

#include <optional>
#include <string>
#include <vector>

namespace ddsimp::server {

class Tokens {
public:
    Tokens() = default;
    // --token (named "token") and the lines "NAME TOKEN" of --tokens-file (blank lines and lines
    // starting with '#' skipped). Throws std::runtime_error naming the file and line.
    explicit Tokens(const Config& config);

    bool required() const { return !tokens_.empty(); }
    // The name of the token equal to `presented`, or nothing. Every token is compared in full, so
    // the time does not tell how much of one matched.
    std::optional<std::string> match(const std::string& presented) const;

private:
    struct Named {
        std::string name, token;
    };
    std::vector<Named> tokens_;
};

} // namespace ddsimp::server
