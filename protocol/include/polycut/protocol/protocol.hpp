// Umbrella header of the polycut wire protocol (docs/protocol.md).
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/expected.hpp"
#include "polycut/protocol/frames.hpp"
#include "polycut/protocol/limits.hpp"
#include "polycut/protocol/methods.hpp"
#include "polycut/protocol/params.hpp"
#include "polycut/protocol/reply.hpp"
#include "polycut/protocol/request.hpp"
#include "polycut/protocol/request_id.hpp"
#include "polycut/protocol/results.hpp"
#include "polycut/protocol/stream.hpp"
#include "polycut/protocol/sweep.hpp"
