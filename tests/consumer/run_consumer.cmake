# Installs aggkit from AGGKIT_BUILD_DIR into a scratch prefix, checks that the license and citation files are
# installed with it, and builds + runs the C++ example examples/cpp (find_package(aggkit)) and the installed
# Python module against it.
set(_prefix ${AGGKIT_BUILD_DIR}/consumer-test/prefix)
set(_build ${AGGKIT_BUILD_DIR}/consumer-test/build)
file(REMOVE_RECURSE ${AGGKIT_BUILD_DIR}/consumer-test)
foreach(_step
    "${CMAKE_COMMAND};--install;${AGGKIT_BUILD_DIR};--prefix;${_prefix}"
    "${CMAKE_COMMAND};-S;${CONSUMER_SOURCE_DIR};-B;${_build};-DCMAKE_PREFIX_PATH=${_prefix};-DCMAKE_BUILD_TYPE=Release"
    "${CMAKE_COMMAND};--build;${_build}"
    "${_build}/smoluchowski"
    # The installed Python module, from the prefix's dist-packages (the libraries found through its rpath).
    "${CMAKE_COMMAND};-E;env;PYTHONPATH=${_prefix}/lib/python3/dist-packages;/usr/bin/python3;-c;import aggkit,sys; s = aggkit.integrate(aggkit.Model('constant', size=512), [1.0]); sys.exit(abs(s.moment(0)[0] - 2/3) > 1e-6)")
  execute_process(COMMAND ${_step} RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _out)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "consumer step failed (${_rc}): ${_step}\n${_out}")
  endif()
  if(_step MATCHES "--install")
    foreach(_file LICENSE CITATION.cff)
      if(NOT EXISTS ${_prefix}/share/doc/aggkit/${_file})
        message(FATAL_ERROR "cmake --install put no ${_file} in ${_prefix}/share/doc/aggkit")
      endif()
    endforeach()
  endif()
endforeach()
message(STATUS "${_out}")
