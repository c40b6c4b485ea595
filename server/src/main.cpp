// ddsimp-server: listens for renderers and tools (native protocol and WebSocket), simplifies
// on a thread pool, and stops cleanly on SIGTERM or SIGINT.
#include "admission.h"
#include "config.h"
#include "glb_download.h"
#include "http_server.h"
#include "listener.h"
#include "logging.h"
#include "memory_bound.h"
#include "native_server.h"
#include "service.h"

#include <boost/asio/signal_set.hpp>
#include <spdlog/spdlog.h>

#include <csignal>
#include <iostream>

int main(int argc, char** argv) {
    using namespace ddsimp::server;
    const Config config = parse_config(argc, argv);
    // Under a file size limit (ulimit -f), a write past it fails with EFBIG instead of killing the
    // server, and the upload that caused it gets UNAVAILABLE.
    std::signal(SIGXFSZ, SIG_IGN);
    setup_logging(config);
    try {
        boost::asio::io_context io(1);
        std::unique_ptr<boost::asio::ssl::context> tls;
        if (!config.tls_cert.empty()) {
            tls =
                std::make_unique<boost::asio::ssl::context>(boost::asio::ssl::context::tls_server);
            tls->set_options(boost::asio::ssl::context::no_tlsv1 |
                             boost::asio::ssl::context::no_tlsv1_1);
            tls->use_certificate_chain_file(config.tls_cert);
            tls->use_private_key_file(config.tls_key, boost::asio::ssl::context::pem);
        }
        Service service(io, config);
        const ConnectionLimits limits = fit_descriptor_limit(config);
        Admission admission(limits, service.metrics());
        const MemoryBound bound = memory_bound(config, limits.total);
        service.metrics().memory_bound = int64_t(bound.total());
        spdlog::info("memory clients can make the server hold (docs/operations.md#memory): {}",
                     bound.describe());
        HttpServer http(service, tls.get());
        route_glb_downloads(http);
        const auto address = [](const std::string& a) { return boost::asio::ip::make_address(a); };
        Listener native_port(io, {address(config.bind), config.port},
                             native_protocol(service, tls.get()), admission, service.metrics(),
                             config.timeouts);
        Listener http_port(
            io,
            {address(config.http_bind.empty() ? config.bind : config.http_bind), config.http_port},
            http.protocol(), admission, service.metrics(), config.timeouts);
        boost::asio::signal_set signals(io, SIGTERM, SIGINT);
        signals.async_wait([&](boost::system::error_code, int signal) {
            spdlog::info("signal {}: shutting down", signal);
            native_port.stop();
            http_port.stop();
            service.stop();
        });
        spdlog::info("ddsimp-server ready: ddsimp remote list --server {}:{}", config.bind,
                     config.port);
        io.run();
        spdlog::info("stopped");
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "ddsimp-server: " << e.what() << "\n";
        return 1;
    }
}
