// A test hook for the undo path (issue 12 item 1): makes the next cut calls fail the way a cut on
// an unforeseen configuration fails, after the mesh has been edited, so the tests can drive a
// failing cut through the simulation and the server and check that nothing changed and the
// service went on. Process-wide; production code never arms it.
#pragma once

namespace polycut::cut {

/// Arms `count` failures: each of the next `count` calls to Cutter::cut or SnapCutter::cut edits
/// the mesh and then throws polycut::Error("cut", "injected failure"). 0 disarms.
void inject_cut_failures(int count);

/// Cut calls still armed to fail.
int injected_cut_failures();

namespace detail {
/// Called by the cutters once their edit is made: throws when a failure is armed.
void fail_if_injected();
} // namespace detail

} // namespace polycut::cut
