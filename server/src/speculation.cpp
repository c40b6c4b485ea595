// Speculation: after a surface arrives, while no client's job waits, the server computes the
// records of the default options at a few alphas, each as deep as the surface allows, so that a
// request at any alpha finds a ready record near it for its preview (send_preview). The work
// yields its worker to any client job and starts again later.
#include "service.h"

#include "log_text.h"

#include "ddsimp/protocol/reduction_options.h"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

namespace ddsimp::server {

namespace {

constexpr double kSpeculativeAlphas[] = {0.0, 0.5, 1.0};

} // namespace

void Service::speculate(const std::string& surface) {
    if (!config_.speculate || scheduler_.threads() == 0) return;
    for (double alpha : kSpeculativeAlphas) {
        // The options of a request that gives only the surface and alpha.
        Options defaults;
        defaults.alpha = alpha;
        v1::Request request;
        protocol::set_options(request, defaults);
        ReductionParams params{surface, protocol::options_from(request)};
        const std::string key = protocol::result_key(surface, params.options);
        scheduler_.submit_background([this, params, key](const std::atomic<bool>& yield) {
            static const std::atomic<bool> never{false}; // nobody cancels speculation
            try {
                bool computed = false;
                reductions_.record(params, key, 0, never, &computed, &yield);
                if (computed) ++metrics_.speculative_records;
            } catch (const Cancelled&) {
                if (yield.load()) return false; // a client needed the worker: again later
            } catch (const std::exception& e) { // the surface was removed, or cannot be reduced
                spdlog::info("no speculative record of {} at alpha {}: {}", params.surface,
                             params.options.alpha, loggable(e.what(), 300));
            }
            boost::asio::post(io_, [this, key, params] {
                if (reductions_.cached_record(key, 0)) remember_result(key, params);
            });
            return true;
        });
    }
}

} // namespace ddsimp::server
