// SPDX-License-Identifier: Apache-2.0
// codrive.dump: a candump log or pcap decoded by codrive-dump's library, streamed to Python as
// the lines `codrive-dump --json` prints (the Python side parses them into dicts).
#include "errors.hpp"
#include "module.hpp"

#include <codrive/core/eds.hpp>
#include <codrive/dump/drive_profiles.hpp>
#include <codrive/dump/dumper.hpp>
#include <codrive/dump/input.hpp>

#include <pybind11/stl.h>

#include <cerrno>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <thread>

namespace py = pybind11;

namespace codrive::python {

namespace {

/// Runs dump_input() — the same input detection, readers and decoder as `codrive-dump -r FILE
/// --json` — on a worker thread and hands its output over in chunks, at most kMaxQueued bytes
/// ahead of the reader, so a capture of any size streams in bounded memory.
class TraceStream {
public:
    TraceStream(const std::string& path, const std::map<long, std::string>& eds,
                const std::map<long, std::string>& profiles, double sdo_timeout)
        : path_(path) {
        // open() reads the file's first bytes (is it gzip?): on a pipe that waits for its
        // writer, so other Python threads run meanwhile.
        auto in = [&] {
            py::gil_scoped_release unlocked;
            return dump::BufferedInput::open(path);
        }();
        if (!in) {
            errno = in.error().value();
            PyErr_SetFromErrnoWithFilename(PyExc_OSError, path.c_str());
            throw py::error_already_set();
        }
        input_ = std::move(*in);
        dump::DumpOptions opts;
        opts.line.json = true;
        opts.line.color = false;
        opts.decoder.sdo_timeout_ns = static_cast<std::int64_t>(sdo_timeout * 1e9);
        dumper_ = std::make_unique<dump::Dumper>(
            opts, [this](std::string_view s) { push(s); },
            [this](std::string_view s) {
                std::lock_guard lock(mutex_);
                problems_.emplace_back(s);
            });
        dump::register_drive_profiles(registry_);
        dumper_->decoder().set_profiles(&registry_);
        for (const auto& [node, file] : eds) {
            const NodeId n = node_arg(node, "eds");
            auto desc = load_eds(file, n);
            if (!desc) {
                errno = desc.error().value();
                PyErr_SetFromErrnoWithFilename(PyExc_OSError, file.c_str());
                throw py::error_already_set();
            }
            for (const auto& f : desc->findings) {
                if (f.severity == EdsSeverity::Error) {
                    problems_.push_back(format_finding(f));
                }
            }
            dumper_->decoder().set_description(
                n, std::make_shared<DeviceDescription>(std::move(*desc)));
        }
        for (const auto& [node, name] : profiles) {
            const NodeId n = node_arg(node, "profiles");
            const auto* p = registry_.find(name);
            if (p == nullptr) {
                std::string names;
                for (const auto& known : registry_.all()) {
                    names += (names.empty() ? "" : ", ") + std::string(known->name());
                }
                throw py::value_error("profiles: no profile named '" + name + "' (known: " + names +
                                      ")");
            }
            dumper_->decoder().set_profile(n, p);
        }
        worker_ = std::thread([this] { run(); });
    }

    ~TraceStream() {
        py::gil_scoped_release nogil;
        {
            std::lock_guard lock(mutex_);
            cancelled_ = true;
        }
        space_.notify_all();
        worker_.join();
    }
    TraceStream(const TraceStream&) = delete;
    TraceStream& operator=(const TraceStream&) = delete;

    /// The next chunk of JSON lines, or None at the end of the input. Waits without the GIL.
    py::object next_chunk() {
        std::string chunk;
        {
            py::gil_scoped_release nogil;
            std::unique_lock lock(mutex_);
            data_.wait(lock, [this] { return !chunks_.empty() || done_; });
            if (chunks_.empty()) {
                lock.unlock();
                return py::none();
            }
            chunk = std::move(chunks_.front());
            chunks_.pop_front();
            queued_ -= chunk.size();
        }
        space_.notify_all();
        return py::str(chunk);
    }

    /// Input problems so far ("trace.log:12: bad data byte ..."), in order.
    std::vector<std::string> problems() {
        std::lock_guard lock(mutex_);
        return problems_;
    }
    /// True if reading stopped early: a truncated or unreadable container, a cut or corrupt gzip
    /// stream, or a text file of a format codrive-dump does not read.
    bool fatal() {
        std::lock_guard lock(mutex_);
        return fatal_;
    }
    [[nodiscard]] const std::string& path() const { return path_; }

private:
    static constexpr std::size_t kMaxQueued = 4U << 20;

    static NodeId node_arg(long node, const char* what) {
        if (node < 1 || node > kMaxNodeId) {
            throw py::value_error(std::string(what) + ": node " + std::to_string(node) +
                                  " is not 1..127");
        }
        return static_cast<NodeId>(node);
    }

    void run() {
        const auto sum = dump::dump_input(*input_, path_, *dumper_);
        dumper_->finish();
        std::lock_guard lock(mutex_);
        fatal_ = sum.fatal;
        done_ = true;
        data_.notify_all();
    }

    void push(std::string_view s) {
        std::unique_lock lock(mutex_);
        space_.wait(lock, [this] { return queued_ < kMaxQueued || cancelled_; });
        if (cancelled_) {
            return; // the reader is gone: the rest of the input is read and dropped
        }
        chunks_.emplace_back(s);
        queued_ += s.size();
        data_.notify_all();
    }

    std::string path_;
    std::unique_ptr<dump::BufferedInput> input_;
    dump::ProfileRegistry registry_;
    std::unique_ptr<dump::Dumper> dumper_;
    std::mutex mutex_;
    std::condition_variable data_;
    std::condition_variable space_;
    std::deque<std::string> chunks_;
    std::size_t queued_ = 0;
    std::vector<std::string> problems_;
    bool done_ = false;
    bool fatal_ = false;
    bool cancelled_ = false;
    std::thread worker_;
};

} // namespace

void bind_dump(py::module_& m) {
    py::module_ d = m.def_submodule("dump", "Trace decoding (codrive-dump's library).");
    py::class_<TraceStream>(d, "TraceStream",
                            "codrive-dump --json output of one file, in chunks (use "
                            "codrive.dump.read, which yields dicts).")
        .def(py::init<const std::string&, const std::map<long, std::string>&,
                      const std::map<long, std::string>&, double>(),
             py::arg("path"), py::arg("eds"), py::arg("profiles"), py::arg("sdo_timeout"))
        .def("next_chunk", &TraceStream::next_chunk)
        .def_property_readonly("problems", &TraceStream::problems)
        .def_property_readonly("fatal", &TraceStream::fatal)
        .def_property_readonly("path", &TraceStream::path);
}

} // namespace codrive::python
