#include "core/binary_io.h"

#include <cerrno>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>

#include "core/errors.h"

namespace patina {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "Patina's readers assume a little-endian host");

BinaryReader::BinaryReader(const std::string& path) : m_path(path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw FormatError(path, "", std::string("cannot open: ") + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw FormatError(path, "", "is a directory, not a file");
    m_file = std::fopen(path.c_str(), "rb");
    if (!m_file) throw FormatError(path, "", std::string("cannot open: ") + std::strerror(errno));
    m_size = static_cast<uint64_t>(st.st_size);
}

BinaryReader::~BinaryReader() {
    if (m_file) std::fclose(m_file);
}

void BinaryReader::fail(const std::string& field, const std::string& problem) const {
    throw FormatError(m_path, "byte " + std::to_string(m_offset) + ", " + field, problem);
}

void BinaryReader::require(uint64_t bytes, const char* field) const {
    if (bytes > remaining())
        fail(field, "file is truncated: " + std::to_string(bytes) + " bytes needed, " + std::to_string(remaining()) +
                        " left (file size " + std::to_string(m_size) + ")");
}

void BinaryReader::read(void* dst, size_t bytes, const char* field) {
    require(bytes, field);
    if (bytes && std::fread(dst, 1, bytes, m_file) != bytes) fail(field, "read error");
    m_offset += bytes;
}

uint32_t BinaryReader::u32(const char* field) {
    uint32_t v;
    read(&v, 4, field);
    return v;
}

int32_t BinaryReader::i32(const char* field) {
    int32_t v;
    read(&v, 4, field);
    return v;
}

std::string BinaryReader::string(uint32_t max_bytes, const char* field) {
    const uint32_t n = u32(field);
    if (n > max_bytes) fail(field, "string length " + std::to_string(n) + " exceeds the limit " + std::to_string(max_bytes));
    std::string s(n, '\0');
    read(s.data(), n, field);
    return s;
}

void BinaryWriter::bytes(const void* src, size_t n) {
    const auto* p = static_cast<const uint8_t*>(src);
    m_data.insert(m_data.end(), p, p + n);
}

void BinaryWriter::u32(uint32_t v) { bytes(&v, 4); }

void BinaryWriter::string(const std::string& s) {
    u32(static_cast<uint32_t>(s.size()));
    bytes(s.data(), s.size());
}

void BinaryWriter::commit(const std::string& path) const {
    const std::string tmp = path + ".tmp" + std::to_string(::getpid());
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw FormatError(path, "", std::string("cannot write: ") + std::strerror(errno));
    const bool ok = std::fwrite(m_data.data(), 1, m_data.size(), f) == m_data.size();
    const bool closed = std::fclose(f) == 0;
    if (!ok || !closed) {
        std::remove(tmp.c_str());
        throw FormatError(path, "", "write failed (disk full?)");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        std::remove(tmp.c_str());
        throw FormatError(path, "", std::string("cannot rename the temporary file into place: ") + std::strerror(err));
    }
}

}  // namespace patina
