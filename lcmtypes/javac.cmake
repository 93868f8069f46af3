# Compiles every generated Java type (the list is only known after lcm-gen ran).
file(GLOB_RECURSE sources ${SRC}/*.java)
execute_process(COMMAND ${JAVAC} -nowarn --release 11 -cp ${LCM_JAR} -d ${OUT} ${sources}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "javac failed on the generated LCM types")
endif()
