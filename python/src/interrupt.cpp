// SPDX-License-Identifier: Apache-2.0
#include "interrupt.hpp"

#include <pybind11/pybind11.h>

#include <atomic>
#include <csignal>

namespace codrive::python {
namespace {

std::atomic<bool> g_sigint{false};
static_assert(std::atomic<bool>::is_always_lock_free, "written by a signal handler");
struct sigaction g_python_action {};
unsigned long g_main_thread = 0;

extern "C" void relay_sigint(int sig, siginfo_t* info, void* context) {
    g_sigint.store(true);
    if ((g_python_action.sa_flags & SA_SIGINFO) != 0) {
        g_python_action.sa_sigaction(sig, info, context);
    } else if (g_python_action.sa_handler != SIG_DFL && g_python_action.sa_handler != SIG_IGN) {
        g_python_action.sa_handler(sig);
    }
}

} // namespace

void install_sigint_relay() {
    namespace py = pybind11;
    g_main_thread =
        py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
    struct sigaction current {};
    if (::sigaction(SIGINT, nullptr, &current) != 0 ||
        ((current.sa_flags & SA_SIGINFO) == 0 &&
         (current.sa_handler == SIG_DFL || current.sa_handler == SIG_IGN))) {
        return;
    }
    g_python_action = current;
    struct sigaction relay = current;
    relay.sa_flags |= SA_SIGINFO;
    relay.sa_sigaction = relay_sigint;
    (void)::sigaction(SIGINT, &relay, nullptr);
}

bool on_main_thread() {
    return g_main_thread != 0 && PyThread_get_thread_ident() == g_main_thread;
}

void clear_sigint() {
    g_sigint.store(false);
}

bool sigint_seen() {
    return g_sigint.load();
}

} // namespace codrive::python
