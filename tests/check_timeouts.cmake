# Every ctest test has a TIMEOUT property (a hung test must fail, not hang CI).
#   cmake -DCTEST=ctest -DBIN=<build dir> -DPYTHON=python3 -P check_timeouts.cmake
execute_process(COMMAND ${CTEST} --show-only=json-v1 WORKING_DIRECTORY ${BIN}
                RESULT_VARIABLE rc OUTPUT_VARIABLE json ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ctest --show-only failed: ${err}")
endif()
file(WRITE ${BIN}/tests/ctest_list.json "${json}")
execute_process(COMMAND ${PYTHON} -c "
import json, sys
tests = json.load(open(sys.argv[1]))['tests']
missing = [t['name'] for t in tests if not any(p['name'] == 'TIMEOUT' and float(p['value']) > 0 for p in t.get('properties', []))]
print(len(tests), 'tests,', len(missing), 'without a timeout')
if missing: print('without a timeout:', ', '.join(missing)); sys.exit(1)
if len(tests) < 100: print('suspiciously few tests'); sys.exit(1)
" ${BIN}/tests/ctest_list.json RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${out}${err}")
endif()
message(STATUS "${out}")
