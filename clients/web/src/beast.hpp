// Boost.Beast and Boost.Asio for polycut-web, included in one place: Boost 1.74's
// asio/awaitable.hpp uses std::exchange without including <utility>, which GCC 12's standard
// headers no longer bring in, so <utility> must come first (clang-format would sort it after).
#pragma once

// clang-format off
#include <utility>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
// clang-format on
