#include "python_stream.hpp"

namespace py = pybind11;

namespace tailor::python {

PythonStreamBuf::PythonStreamBuf(py::object target, bool check_signals)
    : target_(std::move(target)), check_signals_(check_signals) {
  if (sigaction(SIGINT, nullptr, &python_handler_) != 0) check_signals_ = false;
}

PythonStreamBuf::~PythonStreamBuf() {
  // The owner may be destroyed while the GIL is released; the reference needs it.
  py::gil_scoped_acquire gil;
  target_ = py::object();
}

PythonStreamBuf::int_type PythonStreamBuf::overflow(int_type c) {
  if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
  pending_.push_back(traits_type::to_char_type(c));
  if (c == '\n') flush_line();
  return c;
}

std::streamsize PythonStreamBuf::xsputn(const char* s, std::streamsize n) {
  pending_.append(s, static_cast<std::size_t>(n));
  if (pending_.find('\n') != std::string::npos) flush_line();
  return n;
}

int PythonStreamBuf::sync() {
  flush_line();
  return 0;
}

void PythonStreamBuf::flush_line() {
  py::gil_scoped_acquire gil;
  if (!pending_.empty() && !target_.is_none()) {
    const std::string text = std::move(pending_);
    pending_.clear();
    try {
      target_.attr("write")(text);
    } catch (py::error_already_set& e) {
      e.restore();
      throw PythonErrorPending();
    }
  }
  pending_.clear();
  if (!check_signals_) return;
  struct sigaction now {};
  if (sigaction(SIGINT, nullptr, &now) != 0 || now.sa_handler != python_handler_.sa_handler) return;
  if (PyErr_CheckSignals() != 0) throw PythonErrorPending();
}

PythonStream::PythonStream(py::object target, bool check_signals)
    : std::ostream(nullptr), buffer_(std::make_unique<PythonStreamBuf>(std::move(target), check_signals)) {
  rdbuf(buffer_.get());
  exceptions(std::ios::badbit);
}

}  // namespace tailor::python
