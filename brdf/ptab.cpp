#include "brdf/ptab.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "core/binary_io.h"
#include "core/crc32.h"
#include "core/errors.h"

namespace patina {

namespace {
constexpr char kMagic[8] = {'P', 'T', 'A', 'B', '\r', '\n', '\x1a', '\n'};
constexpr uint32_t kFlagHasMask = 1u << 0;
constexpr uint32_t kMaxAxisLength = 1u << 20;
constexpr uint32_t kMaxChannels = 4096;
constexpr uint32_t kMaxString = 1u << 20;

size_t padded4(size_t n) { return (n + 3) & ~size_t(3); }

// Offset of the first byte that breaks UTF-8 (overlong forms, surrogates and code points
// above U+10FFFF included), or npos. The text fields are UTF-8 by the spec; checked here so
// that a bad one is reported with its byte, not later as a decoding error in Python.
size_t invalid_utf8(const std::string& s) {
    const auto* p = reinterpret_cast<const unsigned char*>(s.data());
    const size_t n = s.size();
    for (size_t i = 0; i < n;) {
        const unsigned c = p[i];
        size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
        if (len == 0 || i + len > n) return i;
        uint32_t cp = len == 1 ? c : c & (0x7F >> len);
        for (size_t k = 1; k < len; ++k) {
            if ((p[i + k] & 0xC0) != 0x80) return i;
            cp = (cp << 6) | (p[i + k] & 0x3F);
        }
        static const uint32_t kMin[5] = {0, 0, 0x80, 0x800, 0x10000};
        if (cp < kMin[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return i;
        i += len;
    }
    return std::string::npos;
}

std::string utf8_field(BinaryReader& in, const std::string& path, const char* field) {
    std::string s = in.string(kMaxString, field);
    const size_t bad = invalid_utf8(s);
    if (bad != std::string::npos)
        throw FormatError(path, "byte " + std::to_string(in.offset() - s.size() + bad) + ", " + field,
                          std::string("the ") + field + " is not UTF-8 text (byte " + std::to_string(bad) +
                              " of the field)");
    return s;
}
}  // namespace

Table read_ptab(const std::string& path) {
    BinaryReader in(path);
    char magic[8];
    in.read(magic, 8, "magic");
    if (std::memcmp(magic, kMagic, 8) != 0) throw FormatError(path, "byte 0, magic", "not a .ptab file (wrong magic)");
    const uint32_t version = in.u32("version");
    if (version != kPtabVersion)
        in.fail("version", "unsupported .ptab version " + std::to_string(version) + " (this Patina reads version " +
                               std::to_string(kPtabVersion) + ")");
    Table t;
    const uint32_t param = in.u32("parametrization");
    if (param > 2) in.fail("parametrization", "unknown parametrization code " + std::to_string(param));
    t.parametrization = static_cast<Parametrization>(param);
    const uint32_t kind = in.u32("channel_kind");
    if (kind > 3) in.fail("channel_kind", "unknown channel kind code " + std::to_string(kind));
    t.channel_kind = static_cast<ChannelKind>(kind);
    t.symmetry = in.u32("symmetry");
    if (t.symmetry & ~uint32_t(kSymReciprocity | kSymPhiMirror))
        in.fail("symmetry", "unknown symmetry flags " + std::to_string(t.symmetry));
    const uint32_t flags = in.u32("flags");
    if (flags & ~kFlagHasMask) in.fail("flags", "unknown flags " + std::to_string(flags));
    const uint32_t dims = in.u32("dims");
    if (static_cast<int>(dims) != axis_count(t.parametrization))
        in.fail("dims", std::to_string(dims) + " axes, but a " + parametrization_name(t.parametrization) +
                            " table has " + std::to_string(axis_count(t.parametrization)));
    const uint32_t channels = in.u32("channels");
    if (channels < 1 || channels > kMaxChannels)
        in.fail("channels", std::to_string(channels) + " channels (expected 1 to " + std::to_string(kMaxChannels) + ")");
    t.channels = static_cast<int>(channels);
    uint32_t lengths[kMaxAxes];
    uint64_t points = 1;
    for (uint32_t a = 0; a < dims; ++a) {
        lengths[a] = in.u32("axis length");
        if (lengths[a] < 2 || lengths[a] > kMaxAxisLength)
            in.fail("axis length", std::string("axis ") + axis_name(t.parametrization, a) + " has " +
                                       std::to_string(lengths[a]) + " knots (expected 2 to " +
                                       std::to_string(kMaxAxisLength) + ")");
        points *= lengths[a];
        if (points * channels >= (uint64_t(1) << 31)) in.fail("axis length", "table has more than 2^31 values");
    }
    t.units = utf8_field(in, path, "units");
    t.provenance = utf8_field(in, path, "provenance");

    // Everything that follows has a size known now: check it against the file before allocating.
    uint64_t knots = 0;
    for (uint32_t a = 0; a < dims; ++a) knots += lengths[a];
    const bool spectral = t.channel_kind == ChannelKind::Spectral;
    const uint64_t expected = 4 * knots + (spectral ? 4 * uint64_t(channels) : 0) +
                              ((flags & kFlagHasMask) ? padded4(points) : 0) + 4 * points * channels + 4;
    if (expected != in.remaining())
        in.fail("payload", "the header declares " + std::to_string(expected) + " more bytes, the file has " +
                               std::to_string(in.remaining()) + (expected > in.remaining() ? " (truncated)" : " (trailing bytes)"));

    t.axes.resize(dims);
    for (uint32_t a = 0; a < dims; ++a) {
        t.axes[a].resize(lengths[a]);
        in.read(t.axes[a].data(), 4 * size_t(lengths[a]), "axis knots");
    }
    if (spectral) {
        t.wavelengths.resize(channels);
        in.read(t.wavelengths.data(), 4 * size_t(channels), "wavelengths");
    }
    if (flags & kFlagHasMask) {
        std::vector<uint8_t> mask(padded4(points));
        in.read(mask.data(), mask.size(), "validity mask");
        mask.resize(points);
        t.valid = std::move(mask);
    }
    t.values.resize(points * channels);
    const uint64_t payload_offset = in.offset();
    in.read(t.values.data(), 4 * t.values.size(), "values");
    const uint32_t stored_crc = in.u32("checksum");

    // The checksum covers every byte before it; re-read the file once to verify.
    {
        std::vector<uint8_t> all(in.size() - 4);
        std::FILE* f = std::fopen(path.c_str(), "rb");
        const bool ok = f && std::fread(all.data(), 1, all.size(), f) == all.size();
        if (f) std::fclose(f);
        if (!ok) throw FormatError(path, "", "read error while verifying the checksum");
        const uint32_t crc = crc32(0, all.data(), all.size());
        if (crc != stored_crc) throw FormatError(path, "byte " + std::to_string(in.size() - 4) + ", checksum",
                                                 "checksum mismatch: the file is corrupted");
    }
    try {
        t.check();
    } catch (const std::invalid_argument& e) {
        throw FormatError(path, "from byte " + std::to_string(payload_offset) + ", table", e.what());
    }
    return t;
}

void write_ptab(const Table& t, const std::string& path) {
    try {
        t.check();
    } catch (const std::invalid_argument& e) {
        throw FormatError(path, "", std::string("cannot write an invalid table: ") + e.what());
    }
    BinaryWriter out;
    out.bytes(kMagic, 8);
    out.u32(kPtabVersion);
    out.u32(static_cast<uint32_t>(t.parametrization));
    out.u32(static_cast<uint32_t>(t.channel_kind));
    out.u32(t.symmetry);
    const bool has_mask = t.missing_count() > 0;
    out.u32(has_mask ? kFlagHasMask : 0);
    out.u32(static_cast<uint32_t>(t.axes.size()));
    out.u32(static_cast<uint32_t>(t.channels));
    for (const auto& a : t.axes) out.u32(static_cast<uint32_t>(a.size()));
    out.string(t.units);
    out.string(t.provenance);
    for (const auto& a : t.axes) out.bytes(a.data(), 4 * a.size());
    if (t.channel_kind == ChannelKind::Spectral) out.bytes(t.wavelengths.data(), 4 * t.wavelengths.size());
    if (has_mask) {
        std::vector<uint8_t> mask(padded4(t.valid.size()), 0);
        for (size_t j = 0; j < t.valid.size(); ++j) mask[j] = t.valid[j] ? 1 : 0;
        out.bytes(mask.data(), mask.size());
    }
    out.bytes(t.values.data(), 4 * t.values.size());
    out.u32(crc32(0, out.data().data(), out.data().size()));
    out.commit(path);
}

}  // namespace patina
