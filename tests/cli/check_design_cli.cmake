# tmpc design --explicit -> inspect -> export-qp -> solve/simulate with the explicit law
# on a quick variant of the default config, and a corrupted artifact rejected with a message.
file(READ ${SRC}/config/tiltrotor.yaml text)
string(REPLACE "compare_gains: true" "compare_gains: false" text "${text}")
string(REPLACE "verify_directions: 2000" "verify_directions: 100" text "${text}")
# The envelope's scenario files, named from the copy's folder.
string(REGEX REPLACE "([[ ,])scenarios/" "\\1${SRC}/config/scenarios/" text "${text}")
set(dir ${CMAKE_CURRENT_BINARY_DIR}/design_cli)
file(MAKE_DIRECTORY ${dir})
file(WRITE ${dir}/quick.yaml "${text}")
execute_process(COMMAND ${TMPC} design --config ${dir}/quick.yaml --out ${dir}/c.tmpc --report ${dir}/r.json --explicit
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "tightened sets non-empty" OR NOT out MATCHES "regions, complete")
  message(FATAL_ERROR "design failed: ${out}${err}")
endif()
string(REPEAT "0.01," 23 x0)
execute_process(COMMAND ${TMPC} solve --controller ${dir}/c.tmpc --solver explicit --x0 "${x0}0.01"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "explicit: converged")
  message(FATAL_ERROR "solve --solver explicit failed: ${out}${err}")
endif()
string(REPEAT "0.9," 23 far)
execute_process(COMMAND ${TMPC} solve --controller ${dir}/c.tmpc --solver explicit --x0 "${far}0.9"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
# The config's soft constraints: the hard QP is reported infeasible, then the softened QP
# the controller would fly (a slack).
if(NOT rc EQUAL 0 OR NOT out MATCHES "explicit: infeasible" OR NOT out MATCHES "softened QP.*converged.*largest slack")
  message(FATAL_ERROR "a state outside the partition was not reported infeasible: ${out}${err}")
endif()
# The explicit law partitions the nominal state only: with the config's offset-free
# tube law it is refused with a message naming the fix, and flies with Mayne's law.
execute_process(COMMAND ${TMPC} simulate --controller ${dir}/c.tmpc --solver explicit --duration 1 --out ${dir}/sim
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "--tube-law mayne")
  message(FATAL_ERROR "explicit with the offset-free law was not refused clearly: ${out}${err}")
endif()
execute_process(COMMAND ${TMPC} simulate --controller ${dir}/c.tmpc --solver explicit --tube-law mayne --duration 10
                        --out ${dir}/sim RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "fallbacks 0," OR NOT EXISTS ${dir}/sim/metrics.json)
  message(FATAL_ERROR "simulate --solver explicit failed: ${out}${err}")
endif()
# Monte Carlo campaigns and their comparison (Welch t-test over the runs).
foreach(solver admm explicit)
  execute_process(COMMAND ${TMPC} simulate --controller ${dir}/c.tmpc --solver ${solver} --duration 3 --monte-carlo 2
                          --tube-law mayne --seed 4 --out ${dir}/mc_${solver} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT EXISTS ${dir}/mc_${solver}/run_1/metrics.json OR NOT out MATCHES "2 runs")
    message(FATAL_ERROR "simulate --monte-carlo failed: ${out}${err}")
  endif()
endforeach()
execute_process(COMMAND ${TMPC} compare ${dir}/mc_admm/metrics.json ${dir}/mc_explicit/metrics.json
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "Welch" OR NOT out MATCHES "rmse/x")
  message(FATAL_ERROR "compare failed: ${out}${err}")
endif()
execute_process(COMMAND ${TMPC} compare ${dir}/mc_admm/metrics.json ${dir}/r.json RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT err MATCHES "not a tmpc metrics.json")
  message(FATAL_ERROR "compare accepted a design report: ${err}")
endif()
# Plant and controller in real time over a pseudo-terminal pair.
# The estimator chosen on the command line is the one the loop flies (simulate's flags).
execute_process(COMMAND ${TMPC} hil --config ${dir}/quick.yaml --controller ${dir}/c.tmpc --duration 2 --out ${dir}/hil
                --observer residual
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${dir}/hil/metrics.json OR NOT out MATCHES "records, 0 dropped"
   OR NOT out MATCHES "0 rejected" OR NOT out MATCHES "observer residual")
  message(FATAL_ERROR "hil failed: ${out}${err}")
endif()
execute_process(COMMAND ${TMPC} controller --controller ${dir}/c.tmpc --port /dev/null --duration 1
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT err MATCHES "not a terminal")
  message(FATAL_ERROR "a port that is not a terminal was accepted: ${err}")
endif()
# Mission plots (thesis Figures 6.11-6.21) of a single run and of a campaign.
if(PYTHON)
  execute_process(COMMAND ${PYTHON} ${SRC}/scripts/plot_mission.py ${dir}/sim ${dir}/mc_admm
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  foreach(png path_3d position_errors attitude swing tilt inputs solve_times_violin)
    if(NOT EXISTS ${dir}/sim/plots/${png}.png)
      message(FATAL_ERROR "plot_mission.py wrote no ${png}.png: ${out}${err}")
    endif()
  endforeach()
  if(NOT rc EQUAL 0 OR NOT EXISTS ${dir}/mc_admm/run_1/plots/path_3d.png)
    message(FATAL_ERROR "plot_mission.py failed on a campaign: ${out}${err}")
  endif()
endif()
execute_process(COMMAND ${TMPC} solve --controller ${dir}/c.tmpc --solver explicit --explicit ${dir}/missing.tmpcx
                        --x0 "${x0}0.01" RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT err MATCHES "missing.tmpcx: cannot open")
  message(FATAL_ERROR "a missing explicit law was not reported: ${err}")
endif()
execute_process(COMMAND ${TMPC} inspect ${dir}/c.tmpc RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "model tiltrotor: 24 states \\(20 measured\\), 4 inputs" OR NOT out MATCHES "envelope: acceleration")
  message(FATAL_ERROR "inspect failed: ${out}")
endif()
string(REPEAT "0.01," 23 x0)
execute_process(COMMAND ${TMPC} export-qp --controller ${dir}/c.tmpc --x0 "${x0}0.01" --out ${dir}/qp.json
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "16 variables")
  message(FATAL_ERROR "export-qp failed: ${out}${err}")
endif()
execute_process(COMMAND ${TMPC} export-qp --controller ${dir}/c.tmpc --x0 "1,2" --out ${dir}/bad.json
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT err MATCHES "expected 24")
  message(FATAL_ERROR "a short --x0 was accepted: ${err}")
endif()
file(READ ${dir}/c.tmpc bytes HEX)
string(SUBSTRING "${bytes}" 0 2000 head)
file(WRITE ${dir}/truncated.tmpc "")
execute_process(COMMAND ${TMPC} inspect ${dir}/truncated.tmpc RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT err MATCHES "truncated")
  message(FATAL_ERROR "an empty artifact was accepted: ${err}")
endif()
message(STATUS "design --explicit, inspect, export-qp, solve/simulate explicit: ok")
