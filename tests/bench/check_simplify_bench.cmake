# Runs ddsimp_bench briefly on a small surface; fails unless it exits 0 and every benchmark reports
# its triangle counters. Called by ctest with -DBENCH=... -DSURFACE=... -DOUT=...
foreach(var BENCH SURFACE OUT)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "check_simplify_bench.cmake: -D${var}=... is required")
    endif()
endforeach()
file(REMOVE "${OUT}")

execute_process(
    COMMAND "${BENCH}" "--surface=${SURFACE}" --benchmark_min_time=0.01
        "--benchmark_out=${OUT}" --benchmark_out_format=json
    RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
message("${stdout}${stderr}")
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "ddsimp_bench exited with '${rc}', expected 0")
endif()
if(NOT EXISTS "${OUT}")
    message(FATAL_ERROR "ddsimp_bench wrote no ${OUT}")
endif()

file(READ "${OUT}" json)
string(JSON count ERROR_VARIABLE err LENGTH "${json}" benchmarks)
if(err)
    message(FATAL_ERROR "${OUT}: no 'benchmarks' array: ${err}")
endif()

foreach(expected meshopt_simplify ddsimp_EdgeCollapse ddsimp_EdgeCollapse_LeastError
                 ddsimp_VertexRemoval)
    set(found FALSE)
    if(count GREATER 0)
        math(EXPR last "${count} - 1")
        foreach(i RANGE ${last})
            string(JSON name GET "${json}" benchmarks ${i} name)
            if(NOT name MATCHES "^${expected}(/|$)")
                continue()
            endif()
            set(found TRUE)
            string(JSON error_occurred ERROR_VARIABLE err GET "${json}" benchmarks ${i}
                error_occurred)
            if(NOT err AND error_occurred)
                string(JSON message GET "${json}" benchmarks ${i} error_message)
                message(FATAL_ERROR "${name} failed: ${message}")
            endif()
            foreach(counter triangles_in target triangles_out reached_fraction)
                string(JSON ${counter} ERROR_VARIABLE err GET "${json}" benchmarks ${i} ${counter})
                if(err)
                    message(FATAL_ERROR "${name} reports no '${counter}' counter")
                endif()
            endforeach()
            if(NOT triangles_in GREATER 0 OR NOT triangles_out GREATER 0
               OR triangles_out GREATER triangles_in)
                message(FATAL_ERROR "${name}: implausible counters: triangles_in=${triangles_in} "
                                    "triangles_out=${triangles_out}")
            endif()
            message(STATUS "${name}: ${triangles_in} -> ${triangles_out} triangles "
                           "(target ${target})")
        endforeach()
    endif()
    if(NOT found)
        message(FATAL_ERROR "ddsimp_bench did not run '${expected}'")
    endif()
endforeach()
