# Writes one man page with help2man from a program's --help and --version
# (packaging/man/CMakeLists.txt runs it at build time):
#   cmake -DHELP2MAN=help2man -DPROGRAM=path/to/svg2png -DNAME="one line"
#         -DVERSION=0.1 -DINCLUDE=mpvg.h2m -DOUTPUT=svg2png.1
#         -P help2man.cmake
# help2man asks the program for --version; where that fails or prints
# nothing (mpvg-compare has had none) the page gets "PROGRAM (mpvg)
# VERSION" instead (--version-string), and where --help writes only to
# standard error that is read (--no-discard-stderr).
foreach(var HELP2MAN PROGRAM NAME VERSION INCLUDE OUTPUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "help2man.cmake: -D${var}=... is missing")
  endif()
endforeach()
get_filename_component(program_name "${PROGRAM}" NAME)
set(options "")

execute_process(COMMAND "${PROGRAM}" --version
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_QUIET)
if(NOT rc EQUAL 0 OR out STREQUAL "")
  list(APPEND options "--version-string=${program_name} (mpvg) ${VERSION}")
endif()
execute_process(COMMAND "${PROGRAM}" --help
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_QUIET)
if(out STREQUAL "")
  list(APPEND options --no-discard-stderr)
endif()

execute_process(COMMAND "${HELP2MAN}" --no-info "--name=${NAME}" "--include=${INCLUDE}" ${options}
                        "--output=${OUTPUT}.tmp" "${PROGRAM}"
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  file(REMOVE "${OUTPUT}.tmp")
  message(FATAL_ERROR "help2man failed for ${PROGRAM}: ${err}")
endif()
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
