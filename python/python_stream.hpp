#pragma once
// Output of tailor's commands in Python: a std::ostream whose text goes to a Python file-like
// object (its write(), under the GIL, line by line), and that checks Python's signal handlers on
// every line: after a Ctrl-C the next line throws PythonErrorPending (the KeyboardInterrupt stays
// set), which unwinds the C++ call; bindings() turns it back into the Python exception.
#include <pybind11/pybind11.h>

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
