// SPDX-License-Identifier: Apache-2.0
// Ready-made sinks and sources for client transfers: files and in-memory bytes.
#include <codrive/sdo/transfer.hpp>

#include <cerrno>
#include <memory>
#include <sys/stat.h>

namespace codrive::sdo {

UploadSink file_sink(std::FILE* file) {
    UploadSink sink;
    sink.write = [file](std::span<const std::uint8_t> data) {
        return std::fwrite(data.data(), 1, data.size(), file) == data.size();
    };
    return sink;
}

Result<DownloadSource> file_source(const std::string& path) {
    std::FILE* raw = std::fopen(path.c_str(), "rb");
    if (raw == nullptr) {
        return fail_errno(errno);
    }
    std::shared_ptr<std::FILE> file(raw, [](std::FILE* f) { std::fclose(f); });
    struct stat st {};
    if (::fstat(fileno(raw), &st) != 0) {
        return fail_errno(errno);
    }
    DownloadSource source;
    source.size = static_cast<std::size_t>(st.st_size);
    source.read = [file](std::span<std::uint8_t> out) {
        return std::fread(out.data(), 1, out.size(), file.get()) == out.size();
    };
    return source;
}

DownloadSource bytes_source(Bytes data) {
    auto shared = std::make_shared<Bytes>(std::move(data));
    DownloadSource source;
    source.size = shared->size();
    source.read = [shared, pos = std::size_t{0}](std::span<std::uint8_t> out) mutable {
        if (out.size() > shared->size() - pos) {
            return false;
        }
        std::copy_n(shared->begin() + static_cast<std::ptrdiff_t>(pos), out.size(), out.begin());
        pos += out.size();
        return true;
    };
    return source;
}

} // namespace codrive::sdo
