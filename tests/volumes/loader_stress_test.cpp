/// Loader stress (beyond bad_input_test.cpp): sizes whose byte count would overflow 64 bits in
/// every header format, headers that promise a volume at the size limit from a file that holds a
/// few bytes (run under a memory cap, so that a loader that allocates before it checks fails),
/// and a volume exactly at the size limit loaded by `cvc info` under a 4 GiB address-space cap.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/run_program.h"
#include "tests/volumes/test_support.h"
#include "volumes/load_volume.h"
#include "volumes/raw_reader.h"

#if defined(__SANITIZE_ADDRESS__)
#define CVC_TEST_HAS_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CVC_TEST_HAS_ASAN 1
#endif
#endif

namespace volumes {
namespace {

using testing::scratchFolder;
using testing::writeBytes;

/// Expects loadVolume(path) to throw a VolumeError naming the file and containing `problem`.
void expectRefused(const std::string& path, const std::string& problem, const LoadOptions& options = {}) {
    try {
        loadVolume(path, options);
        ADD_FAILURE() << path << ": loaded, expected an error containing '" << problem << "'";
    } catch (const VolumeError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(problem), std::string::npos) << "message: " << message;
        EXPECT_NE(message.find(std::filesystem::path(path).filename().string()), std::string::npos) << message;
    }
}

std::string nrrdHeader(const std::string& sizes, const std::string& encoding = "raw", const std::string& extra = "") {
    return "NRRD0004\ntype: short\ndimension: 3\nsizes: " + sizes +
           "\nspacings: 1 1 1\nendian: little\nencoding: " + encoding + "\n" + (extra.empty() ? "" : extra + "\n") + "\n";
}

std::string mhaHeader(const std::string& dims, const std::string& dataFile = "LOCAL", const std::string& extra = "") {
    return "NDims = 3\nDimSize = " + dims + "\nElementType = MET_SHORT\n" + extra + "ElementDataFile = " + dataFile + "\n";
}

template <typename T>
void put(std::string& bytes, std::size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

/// A NIfTI-1 single file (.nii): 348-byte header, 4 extension bytes, then `data`; int16 voxels,
/// unit pixdim, no qform or sform (offsets from nifti1.h).
std::string niftiOne(const std::array<std::int16_t, 8>& dim, const std::string& data) {
    std::string bytes(352, '\0');
    put(bytes, 0, std::int32_t{348});
    for (int k = 0; k < 8; ++k) put(bytes, 40 + 2 * static_cast<std::size_t>(k), dim[static_cast<std::size_t>(k)]);
    put(bytes, 70, std::int16_t{4});   // datatype: int16
    put(bytes, 72, std::int16_t{16});  // bitpix
    for (int k = 0; k < 8; ++k) put(bytes, 76 + 4 * static_cast<std::size_t>(k), 1.0f);
    put(bytes, 108, 352.0f);  // vox_offset
    put(bytes, 123, char{2});  // xyzt_units: mm
    std::memcpy(bytes.data() + 344, "n+1\0", 4);
    return bytes + data;
}

/// A NIfTI-2 single file: 540-byte header with int64 dims, 4 extension bytes, then `data`
/// (offsets from nifti2.h).
std::string niftiTwo(const std::array<std::int64_t, 8>& dim, const std::string& data) {
    std::string bytes(544, '\0');
    put(bytes, 0, std::int32_t{540});
    std::memcpy(bytes.data() + 4, "n+2\0\r\n\032\n", 8);
    put(bytes, 12, std::int16_t{4});   // datatype: int16
    put(bytes, 14, std::int16_t{16});  // bitpix
    for (int k = 0; k < 8; ++k) put(bytes, 16 + 8 * static_cast<std::size_t>(k), dim[static_cast<std::size_t>(k)]);
    for (int k = 0; k < 8; ++k) put(bytes, 104 + 8 * static_cast<std::size_t>(k), 1.0);
    put(bytes, 168, std::int64_t{544});  // vox_offset
    put(bytes, 500, std::int32_t{2});    // xyzt_units: mm
    return bytes + data;
}

TEST(LoaderStress, SizesWhoseByteCountOverflowsAreRefused) {
    const std::string folder = scratchFolder("stress_overflow");
    // 2^64 + 1, 2^32 + 1 (1 after a 32-bit wrap), 2^63 - 1: as sizes each is refused by name, and
    // no product of them is ever formed.
    for (const std::string& sizes : {std::string("18446744073709551617 1 1"), std::string("4294967297 1 1"),
                                     std::string("9223372036854775807 9223372036854775807 2"),
                                     std::string("1 -9223372036854775808 1"), std::string("1e30 1 1")}) {
        writeBytes(folder + "/v.nrrd", nrrdHeader(sizes) + std::string(16, '\0'));
        try {
            loadVolume(folder + "/v.nrrd");
            ADD_FAILURE() << "sizes " << sizes << " loaded";
        } catch (const VolumeError& e) {
            const std::string message = e.what();
            EXPECT_TRUE(message.find("are not three integers") != std::string::npos ||
                        message.find("outside 1..4096") != std::string::npos)
                << sizes << ": " << message;
        }
        writeBytes(folder + "/v.mha", mhaHeader(sizes) + std::string(16, '\0'));
        expectRefused(folder + "/v.mha", "DimSize");
        std::string spec = sizes;
        for (char& c : spec) c = c == ' ' ? 'x' : c;
        EXPECT_THROW(parseRawSpec(spec + ":int16:1x1x1"), VolumeError) << spec;
    }
    // NIfTI-2 stores int64 sizes.
    writeBytes(folder + "/wide.nii", niftiTwo({3, 4294967297LL, 1, 1, 1, 1, 1, 1}, std::string(16, '\0')));
    expectRefused(folder + "/wide.nii", "");
    // Four extra dimensions whose product is 1 modulo 2^64: (2^32 + 1)(2^32 - 1) = 2^64 - 1, twice.
    // Multiplied in int64 they wrap (undefined behaviour) to exactly 1, "one volume"; each of
    // them says the file holds more than one.
    const std::int64_t a = (std::int64_t{1} << 32) + 1;
    const std::int64_t b = (std::int64_t{1} << 32) - 1;
    writeBytes(folder + "/wrap.nii", niftiTwo({7, 2, 2, 2, a, b, a, b}, std::string(16, '\0')));
    expectRefused(folder + "/wrap.nii", "");
    // NIfTI-1's int16 sizes cannot overflow, but extra dimensions at their largest must not pass.
    writeBytes(folder + "/many.nii", niftiOne({7, 2, 2, 2, 32767, 32767, 32767, 32767}, std::string(16, '\0')));
    expectRefused(folder + "/many.nii", "");
}

/// Runs `cvc info FILE` with the address space capped at `capBytes`.
testing_support::ProgramRun infoUnderCap(const std::string& path, std::uint64_t capBytes) {
    return testing_support::runCvc("info '" + path + "'", "prlimit --as=" + std::to_string(capBytes) + " --");
}

constexpr std::uint64_t kGiB = std::uint64_t{1} << 30;

TEST(LoaderStress, HeadersPromisingTheSizeLimitFromAFewBytes) {
#ifdef CVC_TEST_HAS_ASAN
    GTEST_SKIP() << "AddressSanitizer's shadow memory cannot run under an address-space cap";
#endif
    // Each header asks for 1024^3 int16 voxels (2 GiB, the limit); each file holds 100 bytes of
    // them. Under a 1 GiB cap a loader that allocates the volume before comparing the file's size
    // with the header fails with std::bad_alloc instead of saying the file is truncated.
    const std::string folder = scratchFolder("stress_promise");
    const std::string dims = "1024 1024 1024";
    const std::string few(100, '\0');
    writeBytes(folder + "/attached.nrrd", nrrdHeader(dims) + few);
    writeBytes(folder + "/skip.nrrd", nrrdHeader(dims, "raw", "byte skip: 0") + few);
    writeBytes(folder + "/detached.nhdr", nrrdHeader(dims, "raw", "data file: detached.raw"));
    writeBytes(folder + "/detached.raw", few);
    writeBytes(folder + "/local.mha", mhaHeader(dims) + few);
    writeBytes(folder + "/detached.mhd", mhaHeader(dims, "detached.raw"));
    writeBytes(folder + "/sized.mhd", mhaHeader(dims, "detached.raw", "HeaderSize = 0\n"));
    writeBytes(folder + "/one.nii", niftiOne({3, 1024, 1024, 1024, 1, 1, 1, 1}, few));
    writeBytes(folder + "/two.nii", niftiTwo({3, 1024, 1024, 1024, 1, 1, 1, 1}, few));
    for (const char* name : {"attached.nrrd", "skip.nrrd", "detached.nhdr", "local.mha", "detached.mhd", "sized.mhd",
                             "one.nii", "two.nii"}) {
        const auto run = infoUnderCap(folder + "/" + name, kGiB);
        EXPECT_NE(run.exitCode, 0) << name;
        EXPECT_EQ(run.err.find("bad_alloc"), std::string::npos) << name << " allocated before checking: " << run.err;
        EXPECT_TRUE(run.err.find("truncated") != std::string::npos || run.err.find("fewer than") != std::string::npos)
            << name << ": " << run.err;
        EXPECT_EQ(testing_support::lineCount(run.err), 1) << name << ": " << run.err;
    }
    const auto raw = testing_support::runCvc("info '" + folder + "/detached.raw' --raw 1024x1024x1024:int16:1x1x1",
                                             "prlimit --as=" + std::to_string(kGiB) + " --");
    EXPECT_NE(raw.exitCode, 0);
    EXPECT_NE(raw.err.find("calls for 2147483648"), std::string::npos) << raw.err;

    // Compressed data cannot be sized before it is inflated: those loaders allocate the 2 GiB
    // volume and must then say the stream ended early, which fits under a 4 GiB cap.
    std::string header = nrrdHeader(dims, "gzip");
    writeBytes(folder + "/cut.nrrd", header + testing::deflateBytes(std::string(4096, '\0'), true));
    writeBytes(folder + "/cut.mha", mhaHeader(dims, "LOCAL", "CompressedData = True\n") +
                                        testing::deflateBytes(std::string(4096, '\0'), false));
    for (const char* name : {"cut.nrrd", "cut.mha"}) {
        const auto run = infoUnderCap(folder + "/" + name, 4 * kGiB);
        EXPECT_NE(run.exitCode, 0) << name;
        EXPECT_NE(run.err.find("truncated"), std::string::npos) << name << ": " << run.err;
        EXPECT_EQ(testing_support::lineCount(run.err), 1) << name << ": " << run.err;
    }
}

TEST(LoaderStress, VolumeAtTheSizeLimitUnderAFourGibCap) {
#ifdef CVC_TEST_HAS_ASAN
    GTEST_SKIP() << "AddressSanitizer's shadow memory cannot run under an address-space cap";
#endif
    // 1024^3 int16 voxels: exactly kMaxVoxelCount, 2 GiB of data in a sparse file (no disk used).
    // Under a 4 GiB address-space cap `cvc info` must load it (one copy of the voxels fits) or
    // refuse with one clear line; one voxel more is refused before anything is read.
    const std::string folder = scratchFolder("stress_limit");
    writeBytes(folder + "/limit.nhdr", nrrdHeader("1024 1024 1024", "raw", "data file: limit.raw"));
    {
        std::ofstream data(folder + "/limit.raw", std::ios::binary);
    }
    std::filesystem::resize_file(folder + "/limit.raw", 2 * kGiB);
    const auto run = infoUnderCap(folder + "/limit.nhdr", 4 * kGiB);
    std::filesystem::remove(folder + "/limit.raw");
    if (run.exitCode == 0) {
        EXPECT_NE(run.out.find("1024 x 1024 x 1024"), std::string::npos) << run.out;
    } else {
        EXPECT_EQ(testing_support::lineCount(run.err), 1) << run.err;
        EXPECT_NE(run.err.find("memory"), std::string::npos) << "not a clear refusal: " << run.err;
    }
    writeBytes(folder + "/over.nhdr", nrrdHeader("1024 1024 1025", "raw", "data file: missing.raw"));
    const auto over = infoUnderCap(folder + "/over.nhdr", 4 * kGiB);
    EXPECT_NE(over.exitCode, 0);
    EXPECT_NE(over.err.find("exceed the limit"), std::string::npos) << over.err;
}

}  // namespace
}  // namespace volumes
