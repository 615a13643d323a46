// The first request on a new connection: a WebSocket upgrade (handed to a WsSession) or a
// plain HTTP GET of the web page.
#pragma once

#include <boost/asio/ip/tcp.hpp>

#include "server_core.hpp"

namespace vlpground::viz::detail {

/// Reads the request on `socket` and answers it (server thread).
void serve_connection(boost::asio::ip::tcp::socket socket, ServerCore& core);

}  // namespace vlpground::viz::detail
