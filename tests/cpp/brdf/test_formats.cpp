// .ptab and MERL readers: round trips, and every kind of bad file gives a FormatError
// that names the file and the place (never a crash, never a huge allocation).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <unistd.h>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "brdf/merl.h"
#include "brdf/ptab.h"
#include "core/crc32.h"
#include "core/errors.h"

using namespace patina;

namespace {
std::string temp_path(const std::string& name) {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir ? dir : "/tmp") + "/patina_test_" + std::to_string(::getpid()) + "_" + name;
}

std::vector<uint8_t> read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

Table small_table(bool spectral, bool holes) {
    Table t;
    t.parametrization = Parametrization::Isotropic;
    t.axes = {{0.0f, 0.3f, 0.9f, 1.5f}, {0.0f, 0.5f, 1.5f}, {0.0f, 1.0f, 2.0f, 3.1f, 3.14159f}};
    t.channels = spectral ? 5 : 3;
    t.channel_kind = spectral ? ChannelKind::Spectral : ChannelKind::RGB;
    if (spectral) t.wavelengths = {400, 450, 500, 600, 700};
    t.values.resize(t.point_count() * t.channels);
    for (size_t i = 0; i < t.values.size(); ++i) t.values[i] = 0.01f * float(i % 97);
    if (holes) {
        t.valid.assign(t.point_count(), 1);
        t.valid[7] = 0;
        for (int c = 0; c < t.channels; ++c) t.values[7 * t.channels + c] = 0.0f;
    }
    t.units = "1/sr";
    t.provenance = "unit test \xc3\xa9";
    t.symmetry = kSymReciprocity;
    return t;
}

// Expects read() to throw a FormatError whose message names the file and contains `needle`.
template <class Read>
void expect_format_error(Read read, const std::string& path, const std::string& needle) {
    try {
        read(path);
        FAIL() << "no error for " << path << " (expected '" << needle << "')";
    } catch (const FormatError& e) {
        EXPECT_EQ(e.path, path);
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

void put_u32(std::vector<uint8_t>& b, size_t at, uint32_t v) { std::memcpy(&b[at], &v, 4); }

void refresh_crc(std::vector<uint8_t>& b) {
    const uint32_t crc = crc32(0, b.data(), b.size() - 4);
    put_u32(b, b.size() - 4, crc);
}
}  // namespace

TEST(Ptab, RoundTripIsExact) {
    for (bool spectral : {false, true})
        for (bool holes : {false, true}) {
            const Table t = small_table(spectral, holes);
            const std::string path = temp_path("rt.ptab");
            write_ptab(t, path);
            const Table r = read_ptab(path);
            EXPECT_EQ(r.parametrization, t.parametrization);
            EXPECT_EQ(r.channel_kind, t.channel_kind);
            EXPECT_EQ(r.symmetry, t.symmetry);
            EXPECT_EQ(r.axes, t.axes);
            EXPECT_EQ(r.values, t.values);
            EXPECT_EQ(r.wavelengths, t.wavelengths);
            EXPECT_EQ(r.valid, t.valid);
            EXPECT_EQ(r.units, t.units);
            EXPECT_EQ(r.provenance, t.provenance);
            std::remove(path.c_str());
        }
}

TEST(Ptab, CrcMatchesZlibCheckValue) {
    const char* s = "123456789";
    EXPECT_EQ(crc32(0, s, 9), 0xCBF43926u);  // the standard CRC-32 check value
}

TEST(Ptab, BadFilesGiveClearErrors) {
    const std::string good_path = temp_path("good.ptab");
    write_ptab(small_table(false, true), good_path);
    const std::vector<uint8_t> good = read_bytes(good_path);
    const std::string path = temp_path("bad.ptab");

    expect_format_error(read_ptab, temp_path("does-not-exist.ptab"), "cannot open");

    write_bytes(path, {});
    expect_format_error(read_ptab, path, "truncated");

    auto b = good;
    b[0] = 'X';
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "magic");

    b = good;
    put_u32(b, 8, 99);
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "version 99");

    b = good;
    put_u32(b, 12, 7);
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "parametrization");

    b = good;
    put_u32(b, 28, 4);  // dims
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "4 axes");

    b = good;
    put_u32(b, 36, 1000000);  // first axis length: declares far more data than the file holds
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "truncated");

    b = good;
    put_u32(b, 36, 0xFFFFFFFFu);
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "knots");

    b = good;
    b.resize(b.size() - 9);
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "truncated");

    b = good;
    b.push_back(0);
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "trailing");

    b = good;
    b[b.size() - 20] ^= 0x40;  // flip a bit in the payload
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "checksum");

    // A NaN value with a valid checksum: caught by the table check, with its grid point.
    b = good;
    const float nan = std::nanf("");
    std::memcpy(&b[b.size() - 8], &nan, 4);
    refresh_crc(b);
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "not finite");

    // Axis knots out of order, valid checksum.
    b = good;
    const size_t header = 8 + 4 * 7 + 4 * 3;
    const uint32_t units_len = *reinterpret_cast<const uint32_t*>(&b[header]);
    const size_t prov_at = header + 4 + units_len;
    const uint32_t prov_len = *reinterpret_cast<const uint32_t*>(&b[prov_at]);
    const size_t knots_at = prov_at + 4 + prov_len;
    const float backwards = 5.0f;
    std::memcpy(&b[knots_at + 4], &backwards, 4);
    refresh_crc(b);
    write_bytes(path, b);
    expect_format_error(read_ptab, path, "strictly increasing");

    std::remove(path.c_str());
    std::remove(good_path.c_str());
}

TEST(Ptab, WriterRefusesInvalidTablesAndLeavesNothing) {
    Table t = small_table(false, false);
    t.values[3] = std::nanf("");
    const std::string path = temp_path("never.ptab");
    EXPECT_THROW(write_ptab(t, path), FormatError);
    EXPECT_FALSE(std::ifstream(path).good());
}

namespace {
std::vector<uint8_t> merl_bytes(int32_t d0, int32_t d1, int32_t d2, size_t values, double fill) {
    std::vector<uint8_t> b(12 + values * 8);
    const int32_t dims[3] = {d0, d1, d2};
    std::memcpy(b.data(), dims, 12);
    for (size_t i = 0; i < values; ++i) {
        const double v = fill + 1e-3 * double(i % 1000);
        std::memcpy(&b[12 + 8 * i], &v, 8);
    }
    return b;
}
constexpr size_t kMerlValues = 3u * 90 * 90 * 180;
}  // namespace

TEST(Merl, ReadsLayoutScalesAndMissingMarkers) {
    auto b = merl_bytes(90, 90, 180, kMerlValues, 1.0);
    // Mark (theta_h 10, theta_d 20, phi_d 30) missing in the green channel only.
    const size_t n = 90u * 90 * 180;
    const size_t idx = 30 + 180 * (20 + 90 * 10);
    const double marker = -1.0;
    std::memcpy(&b[12 + 8 * (n + idx)], &marker, 8);
    const std::string path = temp_path("t.binary");
    write_bytes(path, b);
    const Table t = read_merl(path);
    EXPECT_EQ(t.parametrization, Parametrization::HalfDiff);
    ASSERT_EQ(t.axes[0].size(), 90u);
    ASSERT_EQ(t.axes[2].size(), 181u);
    EXPECT_NEAR(t.axes[0][9], 81.0 / 90.0 * M_PI / 180.0, 1e-7);  // i^2/90 degrees
    EXPECT_NEAR(t.axes[2][180], M_PI, 1e-6);
    // value at (h, d, p) = raw[c * n + src] * scale[c]
    const size_t h = 3, d = 40, p = 100, src = p + 180 * (d + 90 * h), dst = p + 181 * (d + 90 * h);
    const double raw_r = 1.0 + 1e-3 * double(src % 1000), raw_b = 1.0 + 1e-3 * double((2 * n + src) % 1000);
    EXPECT_FLOAT_EQ(t.values[dst * 3 + 0], float(raw_r / 1500.0));
    EXPECT_FLOAT_EQ(t.values[dst * 3 + 2], float(raw_b * 1.66 / 1500.0));
    // the phi_d = 180 knot repeats phi_d = 0
    const size_t seam = 180 + 181 * (d + 90 * h), zero = 0 + 181 * (d + 90 * h);
    EXPECT_EQ(t.values[seam * 3 + 1], t.values[zero * 3 + 1]);
    // the missing point is masked and zeroed in every channel
    const size_t missing = 30 + 181 * (20 + 90 * 10);
    ASSERT_EQ(t.valid.size(), t.point_count());
    EXPECT_EQ(t.valid[missing], 0);
    EXPECT_EQ(t.missing_count(), 1u);
    EXPECT_EQ(t.values[missing * 3], 0.0f);
    EXPECT_NE(t.provenance.find("missing: 1 of"), std::string::npos);
    std::remove(path.c_str());
}

TEST(Merl, BadFilesGiveClearErrors) {
    const std::string path = temp_path("bad.binary");
    write_bytes(path, {1, 2, 3});
    expect_format_error(read_merl, path, "truncated");
    write_bytes(path, merl_bytes(90, 90, 90, 10, 1.0));
    expect_format_error(read_merl, path, "90 x 90 x 180");
    write_bytes(path, merl_bytes(-5, 90, 180, 10, 1.0));
    expect_format_error(read_merl, path, "dims");
    write_bytes(path, merl_bytes(90, 90, 180, kMerlValues - 1, 1.0));
    expect_format_error(read_merl, path, "truncated");
    auto b = merl_bytes(90, 90, 180, kMerlValues, 1.0);
    b.push_back(0);
    write_bytes(path, b);
    expect_format_error(read_merl, path, "trailing");
    b.pop_back();
    const double nan = std::nan("");
    std::memcpy(&b[12 + 8 * 12345], &nan, 8);
    write_bytes(path, b);
    expect_format_error(read_merl, path, "not finite");
    std::remove(path.c_str());
}
