// SPDX-License-Identifier: Apache-2.0
// Which sanitizer a test binary is built with, for the few tests whose bounds or abilities
// depend on it. GCC defines __SANITIZE_THREAD__; clang (the sanitizer builds of tests/run-all.sh)
// only answers __has_feature(thread_sanitizer), so both are asked.
#pragma once

#if defined(__SANITIZE_THREAD__)
#define CODRIVE_TESTING_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define CODRIVE_TESTING_TSAN 1
#endif
#endif
