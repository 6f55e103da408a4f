cmake_minimum_required(VERSION 3.20)  # policies for script mode
# Writes OUTPUT with the git revision of SOURCE_DIR as a C++ macro, at every build: a revision
# read when CMake configures goes stale with each commit built incrementally. configure_file
# rewrites OUTPUT only when the text changes, so an unchanged revision recompiles nothing.
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE MFDEM_GIT_REVISION OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT MFDEM_GIT_REVISION)
  set(MFDEM_GIT_REVISION "unknown")
endif()
file(CONFIGURE OUTPUT ${OUTPUT} CONTENT "#pragma once\n#define MFDEM_GIT_REVISION \"@MFDEM_GIT_REVISION@\"\n" @ONLY)
