# Python package (python/): decides VLPGROUND_BUILD_PYTHON, ON when pybind11 and a Python 3
# interpreter with numpy and its headers are found (never in sanitizer builds: the module
# would need the sanitizer runtime preloaded into the interpreter).
#
# The interpreter: -DPython3_EXECUTABLE=... if given, else the first `python3` on the PATH
# that can import numpy (a pyenv or venv python without numpy is passed over for the
# system's), else whatever FindPython3 picks.
if(NOT Python3_EXECUTABLE AND NOT VLPGROUND_SANITIZE)
  string(REPLACE ":" ";" _vlpground_path "$ENV{PATH}")
  foreach(_dir IN LISTS _vlpground_path ITEMS /usr/bin)
    if(EXISTS "${_dir}/python3")
      execute_process(COMMAND "${_dir}/python3" -c "import numpy"
                      RESULT_VARIABLE _vlpground_rc OUTPUT_QUIET ERROR_QUIET)
      if(_vlpground_rc EQUAL 0)
        set(Python3_EXECUTABLE "${_dir}/python3" CACHE FILEPATH "Python interpreter for the vlpground module")
        break()
      endif()
    endif()
  endforeach()
endif()

set(_vlpground_python_default OFF)
if(NOT VLPGROUND_SANITIZE)
  find_package(Python3 3.9 COMPONENTS Interpreter Development.Module QUIET)
  if(Python3_FOUND)
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
  if(Python3_FOUND AND pybind11_FOUND)
    set(_vlpground_python_default ON)
  endif()
endif()
option(VLPGROUND_BUILD_PYTHON "Build the Python package (pybind11)" ${_vlpground_python_default})
if(VLPGROUND_BUILD_PYTHON)
  if(NOT pybind11_FOUND)
    find_package(Python3 3.9 REQUIRED COMPONENTS Interpreter Development.Module)
    find_package(pybind11 2.6 CONFIG REQUIRED)
  endif()
  message(STATUS "vlpground: Python package for ${Python3_EXECUTABLE} (pybind11 ${pybind11_VERSION})")
endif()
