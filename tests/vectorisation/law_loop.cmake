# LawLoopVectorises (CTest): the contact laws' loop over a block of pairs
# (Lanes::evaluate_all, forces/evaluate.hpp) must stay a vector loop. It is most of the
# fixed steps' arithmetic, and it has stopped vectorising twice without any test noticing: a
# branch in a law (Mindlin's early return) and a select on a plain flag (model H's dashpot)
# made it scalar and the runs 20-35 % slower, bit for bit the same (docs/performance.md).
# Each law below is compiled alone (tests/vectorisation/law_loop_probe.cpp) with the build's
# optimisation flags, and GCC's vectoriser report must say "loop vectorized".
#   cmake -DSOURCE_DIR=<repository> -DCOMPILER=<g++> "-DFLAGS=<flags>" -P tests/vectorisation/law_loop.cmake
cmake_minimum_required(VERSION 3.25)

# normal law, tangential law, number type (double: fixed steps; Dual: block steps' rates),
# and the rolling law where it is not NoRolling.
set(laws
  LinearDashpot,NoFriction,double      LinearDashpot,MindlinSlip,double
  HertzTsuji,NoFriction,double         HertzTsuji,MindlinSlip,double
  HertzSediment,NoFriction,double      HertzSediment,MindlinSlip,double
  EnergyConserving,NoFriction,double   EnergyConserving,MindlinSlip,double
  EnergyConserving2005,NoFriction,double EnergyConserving2005,MindlinSlip,double
  LinearDashpot,MindlinSlip,Dual       HertzTsuji,MindlinSlip,Dual
  HertzSediment,NoFriction,Dual        HertzSediment,MindlinSlip,Dual
  HertzTsuji,MindlinSlip,double,ConstantDirectionalTorque HertzTsuji,MindlinSlip,double,ElasticPlasticRolling
  LinearDashpot,MindlinSlip,double,ElasticPlasticRolling)

separate_arguments(flags UNIX_COMMAND "${FLAGS}")
set(failures "")
foreach(law IN LISTS laws)
  string(REPLACE "," ";" parts "${law}")
  list(GET parts 0 normal)
  list(GET parts 1 tangential)
  list(GET parts 2 number)
  set(rolling NoRolling)
  list(LENGTH parts n_parts)
  if(n_parts GREATER 3)
    list(GET parts 3 rolling)
  endif()
  execute_process(
    COMMAND ${COMPILER} ${flags} -I${SOURCE_DIR}/src -DPROBE_NORMAL=${normal} -DPROBE_TANGENTIAL=${tangential}
            -DPROBE_ROLLING=${rolling} -DPROBE_NUMBER=${number} -fopt-info-vec-optimized -c ${SOURCE_DIR}/tests/vectorisation/law_loop_probe.cpp -o /dev/null
    RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT status EQUAL 0)
    list(APPEND failures "${normal} + ${tangential} + ${rolling} on ${number}: the probe does not compile:\n${out}")
  elseif(NOT out MATCHES "loop vectorized")
    list(APPEND failures "${normal} + ${tangential} + ${rolling} on ${number}: the law loop is not vectorised (see -fopt-info-vec-missed)")
  endif()
endforeach()
if(failures)
  string(REPLACE ";" "\n" failures "${failures}")
  message(FATAL_ERROR "${failures}")
endif()
list(LENGTH laws count)
message(STATUS "the law loop is vectorised for all ${count} laws")
