// SPDX-License-Identifier: Apache-2.0
// Ctrl-C while Python's main thread waits on a real bus: the transfers end (the node gets an SDO
// abort) and KeyboardInterrupt is raised, instead of the wait going on until they end by
// themselves.
#pragma once

namespace codrive::python {

/// Puts a SIGINT handler in front of Python's (call with the GIL, at import): it records the
/// signal and then runs Python's handler, so Python raises KeyboardInterrupt as it always does.
/// Nothing is installed when SIGINT is not Python's (ignored, default, or another program's);
/// a later signal.signal(SIGINT, ...) replaces the relay, and waits are then not interrupted.
void install_sigint_relay();
/// True on Python's main thread (the one KeyboardInterrupt is raised in).
bool on_main_thread();
/// Forgets a recorded SIGINT (a wait starts).
void clear_sigint();
/// True if SIGINT came since clear_sigint().
bool sigint_seen();

} // namespace codrive::python
