// Offline recording when the simulation is not part of the build (POLYCUT_ONLY without sim or
// server): the option exists but says how to get it.
#include "offline_recorder.hpp"
#include "polycut/common/error.hpp"

namespace polycut::record {

bool offline_available() {
    return false;
}

OfflineSummary record_offline(const OfflineOptions&, const RecordRender&, const SinkFactory&) {
    throw Error("--offline",
        "this polycut-record was built without the simulation (configure with sim and server)");
}

} // namespace polycut::record
