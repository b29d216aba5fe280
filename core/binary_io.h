// Little-endian binary reading and atomic writing for Patina's file formats.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace patina {

// Reads a file sequentially, checking every read against the bytes present and
// throwing FormatError("path", "byte N (field)", problem) when they are not.
class BinaryReader {
public:
    explicit BinaryReader(const std::string& path);
    ~BinaryReader();
    BinaryReader(const BinaryReader&) = delete;
    BinaryReader& operator=(const BinaryReader&) = delete;

    uint64_t size() const { return m_size; }
    uint64_t offset() const { return m_offset; }
    uint64_t remaining() const { return m_size - m_offset; }
    const std::string& path() const { return m_path; }

    void read(void* dst, size_t bytes, const char* field);
    uint32_t u32(const char* field);
    int32_t i32(const char* field);
    std::string string(uint32_t max_bytes, const char* field);  // u32 length, then bytes
    // Fails before allocating if fewer than count * size bytes remain.
    void require(uint64_t bytes, const char* field) const;
    [[noreturn]] void fail(const std::string& field, const std::string& problem) const;

private:
    std::string m_path;
    std::FILE* m_file = nullptr;
    uint64_t m_size = 0;
    uint64_t m_offset = 0;
};

// Collects bytes in memory, then writes them to `path` through a temporary file
// in the same directory and a rename, so a failure never leaves a half-written file.
class BinaryWriter {
public:
    void bytes(const void* src, size_t n);
    void u32(uint32_t v);
    void string(const std::string& s);
    const std::vector<uint8_t>& data() const { return m_data; }
    void commit(const std::string& path) const;

private:
    std::vector<uint8_t> m_data;
};

}  // namespace patina
