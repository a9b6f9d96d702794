// The ROS faces' send path in epuck_vrep_compat._core: BatchWriter (non-blocking, batched
// writes with bounded per-connection backlogs). A thin shim: it takes bytes, releases the GIL
// while the sockets are written, and leaves all behaviour to the core.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "epuck_vrep_compat/transport/batch_writer.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace evc {
namespace {

py::list report_list(const std::vector<WriterReport>& reports) {
  py::list out;
  for (const WriterReport& r : reports) {
    out.append(py::make_tuple(r.id, r.dropped_batches, r.failed));
  }
  return out;
}

}  // namespace

void bind_wire(py::module_& m) {
  // A descriptor that cannot be duplicated (EMFILE past the limit, EBADF) is an OSError with
  // its errno, as Python's own os.dup raises it.
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const std::system_error& e) {
      py::object os_error = py::reinterpret_borrow<py::object>(PyExc_OSError);
      PyErr_SetObject(PyExc_OSError, os_error(e.code().value(), e.what()).ptr());
    }
  });
  py::class_<BatchWriter>(m, "BatchWriter",
                          "Non-blocking batched writes to many sockets, each with a backlog "
                          "bounded by max_backlog_bytes and max_backlog_batches (oldest "
                          "whole batches dropped).")
      .def(py::init<std::size_t, std::size_t>(), "max_backlog_bytes"_a,
           "max_backlog_batches"_a = static_cast<std::size_t>(-1),
           "Each connection's backlog keeps at most max_backlog_bytes and max_backlog_batches "
           "batches (ValueError for 0 batches); the oldest whole batches after the head go.")
      .def_property_readonly("max_backlog_batches", &BatchWriter::max_backlog_batches)
      .def("open", &BatchWriter::open, "fd"_a, "own"_a = true,
           py::call_guard<py::gil_scoped_release>(),
           "Start writing to a socket descriptor, duplicated when own (OSError past the "
           "descriptor limit), else borrowed; returns the connection's id (never reused).")
      .def("close", &BatchWriter::close, "id"_a, py::call_guard<py::gil_scoped_release>(),
           "Forget a connection: its backlog goes, its duplicate descriptor is closed.")
      .def(
          "queue",
          [](BatchWriter& writer, int id, py::buffer data) {
            const py::buffer_info info = data.request();
            writer.queue(id, static_cast<const char*>(info.ptr),
                         static_cast<std::size_t>(info.size * info.itemsize));
          },
          "id"_a, "data"_a,
          "Queue one whole batch (bytes-like, copied) for a connection; a closed connection's "
          "batches are dropped.")
      .def(
          "queue_slices",
          [](BatchWriter& writer, py::buffer data,
             py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> slices) {
            const py::buffer_info info = data.request();
            if (slices.ndim() != 2 || slices.shape(1) != 3) {
              throw std::invalid_argument("slices must have shape (M, 3): id, begin, end");
            }
            const auto rows = slices.unchecked<2>();
            std::vector<BatchWriter::Slice> parts;
            parts.reserve(static_cast<std::size_t>(rows.shape(0)));
            for (py::ssize_t k = 0; k < rows.shape(0); ++k) {
              if (rows(k, 1) < 0 || rows(k, 2) < 0) {
                throw std::out_of_range("slice " + std::to_string(k) + " has a negative bound");
              }
              parts.push_back({static_cast<int>(rows(k, 0)), static_cast<std::size_t>(rows(k, 1)),
                               static_cast<std::size_t>(rows(k, 2))});
            }
            writer.queue_slices(static_cast<const char*>(info.ptr),
                                static_cast<std::size_t>(info.size * info.itemsize), parts.data(),
                                parts.size());
          },
          "data"_a, "slices"_a,
          "Queue bytes [begin, end) of data for connection id, for each row (id, begin, end) of "
          "slices (M, 3); what one connection gets until the next flush grows one batch, in "
          "call order. IndexError, queueing nothing, for a slice outside data.")
      .def(
          "flush",
          [](BatchWriter& writer) {
            std::vector<WriterReport> reports;
            {
              py::gil_scoped_release released;
              reports = writer.flush();
            }
            return report_list(reports);
          },
          "Send what every socket takes now, without blocking and without the GIL; returns "
          "[(id, dropped_batches, failed)] for the connections where something went wrong "
          "(bytes sent: take_sent_bytes).")
      .def("request_flush", &BatchWriter::request_flush,
           "Ask the writer's own thread (started on first use) to flush what is queued now; "
           "returns at once.")
      .def(
          "take_reports",
          [](BatchWriter& writer, bool wait) {
            std::vector<WriterReport> reports;
            {
              py::gil_scoped_release released;
              reports = writer.take_reports(wait);
            }
            return report_list(reports);
          },
          "wait"_a,
          "The reports of the flushes the writer's thread finished since the last call, as "
          "flush() returns them; with wait, after every requested flush is done.")
      .def(
          "take_sent_bytes",
          [](BatchWriter& writer, bool wait) {
            std::vector<SentBytes> sent;
            {
              py::gil_scoped_release released;
              sent = writer.take_sent_bytes(wait);
            }
            py::list out;
            for (const SentBytes& s : sent) out.append(py::make_tuple(s.id, s.bytes));
            return out;
          },
          "wait"_a = true,
          "[(id, bytes)]: what each open connection's socket took since the last call that "
          "returned them (connections that took nothing are left out). Without wait, nothing "
          "while a flush is under way (those bytes come next time).")
      .def_property_readonly("backlog_bytes", &BatchWriter::backlog_bytes,
                             "Bytes waiting in every backlog.")
      .def_property_readonly("connection_count", &BatchWriter::connection_count,
                             "Connections open in the writer.");
}

}  // namespace evc
