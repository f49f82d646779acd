// Our checks of the header values niftilib and GDCM hand the readers (nifti_header_check.h,
// dicom_series_check.h), called directly with the values, as fuzz/fuzz_nifti_header and
// fuzz/fuzz_dicom_series call them. The inputs are kept in fuzz/corpus/ under the names given.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "volumes/dicom_series_check.h"
#include "volumes/nifti_header_check.h"

namespace volumes {
namespace {

/// fuzz/corpus/nifti_header/small_scaled_sform.bin: tests/volumes' 2x2x2 int16 with a sform.
NiftiHeaderValues smallNifti() {
    NiftiHeaderValues header;
    header.dim = {2, 2, 2, 1, 1, 1, 1};
    header.datatype = 4;  // DT_INT16
    header.datatypeName = "INT16";
    header.bytesPerVoxel = 2;
    header.sclSlope = 2.0;
    header.sclInter = -1000.0;
    header.sformCode = 1;
    header.stoXyz = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 2, 0}, {0, 0, 0, 1}}};
    header.dataOffset = 352;
    header.dataFileBytes = 352 + 16;
    return header;
}

std::string niftiRefusal(const NiftiHeaderValues& header) {
    try {
        niftiLayout(header, "v.nii");
    } catch (const VolumeError& e) {
        return e.what();
    }
    return {};
}

TEST(NiftiHeaderCheck, DerivesTheLayoutOfAGoodHeader) {
    const NiftiLayout layout = niftiLayout(smallNifti(), "v.nii");
    EXPECT_EQ(layout.grid.dims, (std::array<int, 3>{2, 2, 2}));
    EXPECT_EQ(layout.grid.spacingMm, glm::dvec3(1, 1, 2));
    EXPECT_EQ(layout.grid.directionLps[0], glm::dvec3(-1, 0, 0));  // RAS x is LPS -x
    EXPECT_EQ(layout.format.type, ScalarType::Int16);
    EXPECT_EQ(layout.format.slope, 2.0);
    EXPECT_EQ(layout.format.intercept, -1000.0);
    EXPECT_EQ(layout.dataOffset, 352u);
    EXPECT_EQ(layout.dataBytes, 16u);
}

TEST(NiftiHeaderCheck, ExtraDimensionsWhoseProductWrapsAreRefused) {
    // fuzz/corpus/nifti_header/extra_dims_product_wraps_to_one.bin: multiplied in int64,
    // (2^32 + 1)(2^32 - 1)(2^32 + 1)(2^32 - 1) overflows (undefined) and wraps to 1, "one volume".
    NiftiHeaderValues header = smallNifti();
    header.ndim = 7;
    const int64_t a = (int64_t{1} << 32) + 1, b = (int64_t{1} << 32) - 1;
    header.dim = {2, 2, 2, a, b, a, b};
    EXPECT_NE(niftiRefusal(header).find("holds more than one volume (dim[4..7] = 4294967297 4294967295"),
              std::string::npos)
        << niftiRefusal(header);
}

TEST(NiftiHeaderCheck, DataTheFileDoesNotHoldIsRefusedFromTheHeader) {
    // fuzz/corpus/nifti_header/promises_more_than_file.bin: 2 GiB promised by a 452-byte file.
    NiftiHeaderValues header = smallNifti();
    header.dim = {1024, 1024, 1024, 1, 1, 1, 1};
    header.dataFileBytes = 452;
    EXPECT_NE(niftiRefusal(header).find("image data is truncated: holds 100 bytes after offset 352, dim and datatype "
                                        "call for 2147483648"),
              std::string::npos)
        << niftiRefusal(header);
    header.dataFileBytes = 100;  // shorter than the offset itself
    EXPECT_NE(niftiRefusal(header).find("holds 0 bytes after offset 352"), std::string::npos) << niftiRefusal(header);
    header.dataFileBytes = -1;  // compressed: the reader finds out while inflating
    EXPECT_EQ(niftiRefusal(header), "");
}

TEST(NiftiHeaderCheck, NegativeOffsetBitpixAndShearAreNamed) {
    NiftiHeaderValues header = smallNifti();
    header.dataOffset = -8;
    EXPECT_NE(niftiRefusal(header).find("vox_offset -8 is negative"), std::string::npos) << niftiRefusal(header);
    header = smallNifti();
    header.bytesPerVoxel = -2;
    EXPECT_NE(niftiRefusal(header).find("bitpix disagrees with datatype INT16"), std::string::npos);
    header = smallNifti();
    header.stoXyz[0][1] = 0.5;  // fuzz/corpus/nifti_header/sheared_sform.bin
    EXPECT_NE(niftiRefusal(header).find("the sform shears the grid"), std::string::npos) << niftiRefusal(header);
    header = smallNifti();
    header.datatype = 1536;
    header.datatypeName = "FLOAT128";
    EXPECT_NE(niftiRefusal(header).find("NIfTI datatype FLOAT128 (1536) is not supported"), std::string::npos);
}

/// fuzz/corpus/dicom_series/axial_ct_int16.bin, smaller: 32x32 int16, slices 1.25 mm apart.
DicomImageValues axialImage() {
    DicomImageValues image;
    image.dims = {32, 32, 1};
    image.spacingMm = {0.7, 0.7, 1.0};
    image.type = ScalarType::Int16;
    image.typeName = "INT16";
    image.bitsStored = 12;
    image.slope = 1.0;
    image.intercept = -1024.0;
    image.bufferBytes = 32 * 32 * 2;
    return image;
}

std::vector<DicomSlice> axialSlices(const std::vector<double>& zMm) {
    std::vector<DicomSlice> slices;
    for (double z : zMm) {
        std::string name = "s";  // appended piece by piece: GCC 12 warns (-Wrestrict) on "s" + a + b
        name += std::to_string(slices.size());
        name += ".dcm";
        slices.push_back({name, {0, 0, z}, {1, 0, 0}, {0, 1, 0}});
    }
    return slices;
}

std::string dicomRefusal(const DicomImageValues& image, std::vector<DicomSlice> slices) {
    try {
        const Volume grid = dicomSeriesGrid("series", image, slices);
        dicomSliceFormat(slices.front().path, grid, image);
    } catch (const VolumeError& e) {
        return e.what();
    }
    return {};
}

TEST(DicomSeriesCheck, SortsSlicesAndDerivesTheGrid) {
    std::vector<DicomSlice> slices = axialSlices({2.5, 0.0, 3.75, 1.25});
    const Volume grid = dicomSeriesGrid("series", axialImage(), slices);
    EXPECT_EQ(grid.dims, (std::array<int, 3>{32, 32, 4}));
    EXPECT_NEAR(grid.spacingMm.z, 1.25, 1e-12);
    EXPECT_EQ(slices.front().path, "s1.dcm");
    const StoredFormat format = dicomSliceFormat("s1.dcm", grid, axialImage());
    EXPECT_EQ(format.intercept, -1024.0);
}

TEST(DicomSeriesCheck, NonFinitePositionsAreRefusedBeforeSorting) {
    // Sorting by a NaN distance breaks std::sort's strict weak ordering (undefined behaviour).
    const std::string message = dicomRefusal(axialImage(), axialSlices({0.0, std::nan(""), 2.5, 1.25}));
    EXPECT_NE(message.find("s1.dcm: ImagePositionPatient or ImageOrientationPatient is not finite"),
              std::string::npos)
        << message;
}

TEST(DicomSeriesCheck, SizesRescaleAndByteCountsAreNamed) {
    DicomImageValues image = axialImage();
    image.dims = {4294967295u, 32, 1};  // would wrap to -1 as int
    EXPECT_NE(dicomRefusal(image, axialSlices({0.0})).find("Columns is 4294967295, expected 1..4096"),
              std::string::npos);
    image = axialImage();
    image.slope = std::numeric_limits<double>::infinity();
    EXPECT_NE(dicomRefusal(image, axialSlices({0.0})).find("RescaleSlope inf and RescaleIntercept -1024 must be finite"),
              std::string::npos)
        << dicomRefusal(image, axialSlices({0.0}));
    image = axialImage();
    image.bufferBytes = 100;
    EXPECT_NE(dicomRefusal(image, axialSlices({0.0})).find("pixel data decodes to 100 bytes, expected 2048"),
              std::string::npos);
    image = axialImage();
    image.type.reset();
    image.typeName = "FLOAT16";
    EXPECT_NE(dicomRefusal(image, axialSlices({0.0})).find("pixel format FLOAT16 is not supported"), std::string::npos);
    EXPECT_NE(dicomRefusal(axialImage(), axialSlices({0.0, 1.0, 1.0})).find("lie at the same position"),
              std::string::npos);
}

TEST(DicomSeriesCheck, MaskingKeepsBitsStoredAndSignExtends) {
    std::vector<unsigned char> bytes = {0xff, 0xff, 0xff, 0x07};  // 0xffff and 0x07ff, 12 bits stored
    maskStoredBits(12, ScalarType::Int16, bytes);
    int16_t values[2];
    std::memcpy(values, bytes.data(), sizeof(values));
    EXPECT_EQ(values[0], -1);    // 0xfff sign-extended
    EXPECT_EQ(values[1], 2047);  // 0x7ff
}

}  // namespace
}  // namespace volumes
