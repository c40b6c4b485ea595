#include "tokens.h"

#include <fstream>
#include <stdexcept>

namespace ddsimp::server {

Tokens::Tokens(const Config& config) {
    if (!config.token.empty()) tokens_.push_back({"token", config.token});
    if (config.tokens_file.empty()) return;
    std::ifstream in(config.tokens_file);
    if (!in) throw std::runtime_error("cannot read --tokens-file " + config.tokens_file);
    int number = 0;
    for (std::string line; std::getline(in, line);) {
        ++number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
        const size_t space = line.find(' ');
        const std::string where = config.tokens_file + ":" + std::to_string(number);
        if (space == 0 || space == std::string::npos || space + 1 == line.size())
            throw std::runtime_error(where + ": not \"NAME TOKEN\"");
        Named t{line.substr(0, space), line.substr(space + 1)};
        for (const Named& other : tokens_) {
            if (other.name == t.name) throw std::runtime_error(where + ": a second " + t.name);
            if (other.token == t.token)
                throw std::runtime_error(where + ": the token of " + other.name + " again");
        }
        tokens_.push_back(std::move(t));
    }
}

std::optional<std::string> Tokens::match(const std::string& presented) const {
    std::optional<std::string> found;
    for (const Named& t : tokens_) {
        unsigned char diff = t.token.size() != presented.size();
        for (size_t i = 0; i < t.token.size(); ++i)
            diff |=
                static_cast<unsigned char>(t.token[i] ^ (i < presented.size() ? presented[i] : 0));
        if (diff == 0) found = t.name;
    }
    return found;
}

} // namespace ddsimp::server
