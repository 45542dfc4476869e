#pragma once
// Output of tailor's commands in Python: a std::ostream whose text goes to a Python file-like
// object (its write(), under the GIL, line by line), and that checks Python's signal handlers on
// every line: after a Ctrl-C the next line throws PythonErrorPending (the KeyboardInterrupt stays
// set), which unwinds the C++ call; without_gil() turns it back into the Python exception.
// While an optimizer runs, SIGINT has tailor's own handler (optimizers/interrupt.hpp: the run
// stops itself and reports) and its lines may come from inside a back-end's C callback, where
// nothing may be thrown: the signals are checked only while SIGINT's handler is the one it had
// when the stream was made (Python's).
#include <pybind11/pybind11.h>
#include <signal.h>

#include <memory>
#include <ostream>
#include <stdexcept>
#include <streambuf>
#include <string>

namespace tailor::python {

// A Python exception is set (the GIL's thread state holds it): rethrow it as
// pybind11::error_already_set once the GIL is held again.
struct PythonErrorPending : std::runtime_error {
  PythonErrorPending() : std::runtime_error("a Python exception is pending") {}
};

class PythonStreamBuf : public std::streambuf {
 public:
  // `target`: None (text dropped) or an object with write(str). Holds a reference to it.
  PythonStreamBuf(pybind11::object target, bool check_signals);
  ~PythonStreamBuf() override;

 protected:
  int_type overflow(int_type c) override;
  std::streamsize xsputn(const char* s, std::streamsize n) override;
  int sync() override;

 private:
  void flush_line();  // may throw PythonErrorPending
  pybind11::object target_;
  bool check_signals_;
  struct sigaction python_handler_ {};  // SIGINT's when the stream was made
  std::string pending_;
};

// The stream over a PythonStreamBuf; exceptions of the buffer reach the caller (badbit).
class PythonStream : public std::ostream {
 public:
  PythonStream(pybind11::object target, bool check_signals);

 private:
  std::unique_ptr<PythonStreamBuf> buffer_;
};

}  // namespace tailor::python
