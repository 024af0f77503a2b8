// leafdig_asan_python: a Python interpreter with `leafdig._leafdig` built in, for running the
// module's pytest suite under AddressSanitizer + UndefinedBehaviorSanitizer.
//
// Why an interpreter of our own (decided here): the sanitizer builds compile the libraries as
// position-dependent code for executables, which a Python extension (a shared object) cannot
// link, and Debian's python3 does not load the sanitizers' runtime without LD_PRELOAD. Linked
// as a program, the module's one translation unit (python/leafdig_module.cpp, unchanged) and
// the same static libraries run with the sanitizers' runtime in the process from the start.
//
// It takes Python's own command line (`leafdig_asan_python -m pytest tests/python`): the
// module object is made before anything runs and placed in sys.modules as leafdig._leafdig,
// where the package's `from . import _leafdig` finds it (Python's built-in importer looks up
// top-level names only). The package itself (python/leafdig/__init__.py) comes from
// PYTHONPATH as usual.
#include <Python.h>

#include <cstdio>

extern "C" PyObject* PyInit__leafdig();  // NOLINT(readability-identifier-naming): pybind11's name

namespace {

int fail(PyConfig& config, PyStatus status) {
  PyConfig_Clear(&config);
  if (PyStatus_IsExit(status) != 0) return status.exitcode;
  Py_ExitStatusException(status);  // prints the reason and exits
}

}  // namespace

int main(int argc, char** argv) {
  PyConfig config;
  PyConfig_InitPythonConfig(&config);
  PyStatus status = PyConfig_SetBytesArgv(&config, argc, argv);
  if (PyStatus_Exception(status) != 0) return fail(config, status);
  status = Py_InitializeFromConfig(&config);
  if (PyStatus_Exception(status) != 0) return fail(config, status);
  PyConfig_Clear(&config);

  PyObject* module = PyInit__leafdig();
  if (module == nullptr || PyDict_SetItemString(PyImport_GetModuleDict(), "leafdig._leafdig", module) != 0) {
    PyErr_Print();
    std::fputs("leafdig_asan_python: the built-in leafdig._leafdig module could not be made\n", stderr);
    return 1;
  }
  Py_DECREF(module);
  return Py_RunMain();
}
