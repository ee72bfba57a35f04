// SPDX-License-Identifier: Apache-2.0
// The counting operator new/delete of allocation_tests, whose test files are compiled with
// CODRIVE_COUNTING_NEW_ELSEWHERE (so that several of them can include counting_new.hpp). Kept out
// of the unity batch (tests/CMakeLists.txt): the macro is undefined here only.
#undef CODRIVE_COUNTING_NEW_ELSEWHERE
#include <codrive/testing/counting_new.hpp>
