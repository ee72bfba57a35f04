# SPDX-License-Identifier: Apache-2.0
# Helper functions shared by every module: warnings, sanitizers, library and test targets.

function(codrive_set_warnings target)
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wconversion -Wshadow)
    # GCC 12 reports -Wrestrict false positives inside libstdc++ string code at -O3
    # (GCC bug 105329); they are not about our code.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
        target_compile_options(${target} PRIVATE -Wno-restrict)
    endif()
    # Clang's -Wconversion also turns on -Wsign-conversion, which GCC's does not in C++, and
    # clang flags lambda captures used only in some `if constexpr` branches of a template
    # (GCC has no such warning); keep the two compilers to the same warning set (clang is used
    # for the libFuzzer build).
    if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
        target_compile_options(${target} PRIVATE -Wno-sign-conversion -Wno-unused-lambda-capture)
    endif()
    if(CODRIVE_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()

if(CODRIVE_SANITIZE)
    add_compile_options(-fsanitize=${CODRIVE_SANITIZE} -fno-omit-frame-pointer
                        -fno-sanitize-recover=all)
    add_link_options(-fsanitize=${CODRIVE_SANITIZE})
endif()

# codrive_add_module(NAME <name> [DEPS targets...] [PRIVATE_DEPS targets...])
# Builds <module>/src/*.cpp into library codrive_<name>, alias codrive::<name>, public headers in
# <module>/include. The module is exported and installed.
function(codrive_add_module)
    cmake_parse_arguments(ARG "" "NAME" "DEPS;PRIVATE_DEPS" ${ARGN})
    file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
    set(target codrive_${ARG_NAME})
    if(NOT sources)
        message(STATUS "codrive: module ${ARG_NAME} has no sources yet; skipped")
        return()
    endif()
    add_library(${target} STATIC ${sources})
    add_library(codrive::${ARG_NAME} ALIAS ${target})
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${ARG_NAME}
                                               OUTPUT_NAME codrive_${ARG_NAME})
    target_include_directories(${target} PUBLIC
        $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
        $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
        PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_link_libraries(${target} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    # The public headers use C++20 (std::span, concepts): a consumer gets -std=c++20 from the
    # exported target even when its own project does not ask for it.
    target_compile_features(${target} PUBLIC cxx_std_20)
    codrive_set_warnings(${target})
    codrive_unity(${target})
    install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    set_property(GLOBAL APPEND PROPERTY CODRIVE_EXPORTED_TARGETS ${target})
endfunction()

# codrive_add_tool(NAME <exe> SOURCES ... DEPS ...)
# codrive_unity(target): compile the target's sources in batches when CODRIVE_UNITY is on.
function(codrive_unity target)
    if(CODRIVE_UNITY)
        set_target_properties(${target} PROPERTIES UNITY_BUILD ON
                              UNITY_BUILD_BATCH_SIZE ${CODRIVE_UNITY_BATCH})
    endif()
endfunction()

# ONE_UNIT: compile all of the tool's sources as one translation unit (with CODRIVE_UNITY): for a
# tool whose sources all include CLI11, which is header-only in Debian 12 and costs about 7 s
# (clang -O0) to 12 s (GCC -O3) of compile time in every unit that includes it.
function(codrive_add_tool)
    cmake_parse_arguments(ARG "ONE_UNIT" "NAME" "SOURCES;DEPS" ${ARGN})
    add_executable(${ARG_NAME} ${ARG_SOURCES})
    target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS})
    # One truth for `--version`: the project() version, given to the tool's main.cpp only (so
    # the other sources keep the compile flags every build shares), or to the one unit.
    if(ARG_ONE_UNIT AND CODRIVE_UNITY)
        set_target_properties(${ARG_NAME} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 0)
        target_compile_definitions(${ARG_NAME} PRIVATE CODRIVE_VERSION="${PROJECT_VERSION}")
    else()
        foreach(src IN LISTS ARG_SOURCES)
            if(src MATCHES "(^|/)main\\.cpp$")
                set_property(SOURCE ${src} APPEND PROPERTY
                             COMPILE_DEFINITIONS CODRIVE_VERSION="${PROJECT_VERSION}")
            endif()
        endforeach()
    endif()
    codrive_set_warnings(${ARG_NAME})
    install(TARGETS ${ARG_NAME} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()
