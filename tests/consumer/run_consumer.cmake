# Installs aggkit from AGGKIT_BUILD_DIR into a scratch prefix and builds + runs tests/consumer with it.
set(_prefix ${AGGKIT_BUILD_DIR}/consumer-test/prefix)
set(_build ${AGGKIT_BUILD_DIR}/consumer-test/build)
file(REMOVE_RECURSE ${AGGKIT_BUILD_DIR}/consumer-test)
foreach(_step
    "${CMAKE_COMMAND};--install;${AGGKIT_BUILD_DIR};--prefix;${_prefix}"
    "${CMAKE_COMMAND};-S;${CONSUMER_SOURCE_DIR};-B;${_build};-DCMAKE_PREFIX_PATH=${_prefix};-DCMAKE_BUILD_TYPE=Release"
    "${CMAKE_COMMAND};--build;${_build}"
    "${_build}/consumer"
    # The installed Python module, from the prefix's dist-packages (the libraries found through its rpath).
    "${CMAKE_COMMAND};-E;env;PYTHONPATH=${_prefix}/lib/python3/dist-packages;/usr/bin/python3;-c;import aggkit,sys; s = aggkit.integrate(aggkit.Model('constant', size=512), [1.0]); sys.exit(abs(s.moment(0)[0] - 2/3) > 1e-6)")
  execute_process(COMMAND ${_step} RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _out)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "consumer step failed (${_rc}): ${_step}\n${_out}")
  endif()
endforeach()
message(STATUS "${_out}")
