#pragma once
// RAII for the HDF5 C API, shared by the solve writer and the trace writer: one handle closed
// with its matching function, and status checks that turn HDF5 failures into OutputError
// (exit code 4) naming what could not be written.

#include <hdf5.h>

#include <string>

#include "core/error.hpp"

namespace liftoff::io::hdf5 {

class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) throw OutputError("HDF5: cannot open or create " + what);
  }
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

inline void check(herr_t status, const std::string& what) {
  if (status < 0) throw OutputError("HDF5: cannot write " + what);
}

}  // namespace liftoff::io::hdf5
