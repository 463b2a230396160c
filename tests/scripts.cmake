# Tests of the scripts in jobs/ and analysis/ (included from tests/CMakeLists.txt).
# analysis.pytest and jobs.shellcheck are fast (label unit); jobs.slurm starts a
# private one-node Slurm and submits the job scripts (label slurm, about 30 s).

set(RTMINI_PYTHON /usr/bin/python3 CACHE FILEPATH "Python with Debian's numpy, matplotlib, h5py, pytest")
execute_process(COMMAND ${RTMINI_PYTHON} -c "import pytest, h5py, matplotlib, numpy"
                RESULT_VARIABLE _rtmini_py_ok OUTPUT_QUIET ERROR_QUIET)
if(_rtmini_py_ok EQUAL 0)
  add_test(NAME analysis.pytest
           COMMAND ${RTMINI_PYTHON} -m pytest -q -p no:cacheprovider analysis/tests
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(analysis.pytest PROPERTIES LABELS unit TIMEOUT 300)
else()
  message(STATUS "rtmini: ${RTMINI_PYTHON} lacks pytest/h5py/matplotlib/numpy; analysis.pytest not registered")
endif()

find_program(RTMINI_SHELLCHECK shellcheck)
if(RTMINI_SHELLCHECK)
  file(GLOB_RECURSE _rtmini_job_scripts CONFIGURE_DEPENDS
       ${PROJECT_SOURCE_DIR}/jobs/*.sh ${PROJECT_SOURCE_DIR}/jobs/*.sbatch ${PROJECT_SOURCE_DIR}/jobs/*.qsub)
  # -x follows the `source` lines; each script names its sourced file relative to itself.
  add_test(NAME jobs.shellcheck COMMAND ${RTMINI_SHELLCHECK} -x ${_rtmini_job_scripts}
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(jobs.shellcheck PROPERTIES LABELS unit)
else()
  message(STATUS "rtmini: shellcheck not found; jobs.shellcheck not registered")
endif()

# The test runs this build's apps when both are built, else a stub app; RTMINI_BIN
# (a dir holding bake and sketchtrace) in the environment overrides both.
add_test(NAME jobs.slurm COMMAND ${PROJECT_SOURCE_DIR}/jobs/slurm/test/run_local_slurm.sh
         WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(jobs.slurm PROPERTIES LABELS slurm TIMEOUT 240 SKIP_RETURN_CODE 77 RUN_SERIAL ON
                     ENVIRONMENT "RTMINI_BUILD=${PROJECT_BINARY_DIR};RTMINI_PYTHON=${RTMINI_PYTHON}")
