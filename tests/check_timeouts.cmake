# Every ctest test has a TIMEOUT property (a hung test must fail, not hang CI), and the
# missions the label `slow` (the sanitizer variant's ctest -LE leaves them out).
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
def labels(t): return [v for p in t.get('properties', []) if p['name'] == 'LABELS' for v in p['value']]
# The missions carry the label `slow` that the sanitizer variant leaves out (ctest -LE slow).
unlabeled = [t['name'] for t in tests if t.get('command') and t['command'][0].endswith('/test_mission') and 'slow' not in labels(t)]
if unlabeled: print('missions without the label slow:', ', '.join(unlabeled)); sys.exit(1)
if not any('slow' in labels(t) for t in tests): print('no test has the label slow'); sys.exit(1)
" ${BIN}/tests/ctest_list.json RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${out}${err}")
endif()
message(STATUS "${out}")
