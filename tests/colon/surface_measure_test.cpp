// Measuring on a hit image (colon/surface_measure.h, colon/hit_image.h): a hemisphere of known
// radius on a plane, ray cast analytically through a pinhole from above and obliquely, measured
// against its 2r; the two-pixel distance against the analytic hits; reading both NRRD forms of
// `cvc render --hits` and refusing broken ones.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <zlib.h>

#include "colon/colon_error.h"
#include "colon/hit_image.h"
#include "colon/surface_measure.h"

namespace {

namespace fs = std::filesystem;

/// A pinhole camera: rays through pixel centres, row 0 at the top (as engine/render/pinhole_camera.h).
struct Camera {
    glm::dvec3 eye, lookAt, up;
    double fovDeg;
    int size;
    glm::dvec3 ray(int column, int row) const {
        const glm::dvec3 forward = glm::normalize(lookAt - eye);
        const glm::dvec3 right = glm::normalize(glm::cross(forward, up));
        const glm::dvec3 trueUp = glm::cross(right, forward);
        const double t = std::tan(glm::radians(fovDeg) * 0.5);
        const double x = ((column + 0.5) / size * 2.0 - 1.0) * t, y = (1.0 - (row + 0.5) / size * 2.0) * t;
        return glm::normalize(forward + x * right + y * trueUp);
    }
    /// The footprint (mm per pixel) at distance `distance` along the view.
    double footprint(double distance) const { return 2.0 * distance * std::tan(glm::radians(fovDeg) * 0.5) / size; }
};

/// The plane z = 0 (seen from z > 0) with the half ball of radius r centred at the origin on it.
colon::HitImage castHemisphere(const Camera& camera, double r) {
    colon::HitImage image;
    image.width = image.height = camera.size;
    image.hitMm.assign(static_cast<std::size_t>(camera.size * camera.size), glm::dvec3(0.0));
    image.isHit.assign(image.hitMm.size(), 0);
    for (int row = 0; row < camera.size; ++row) {
        for (int column = 0; column < camera.size; ++column) {
            const glm::dvec3 o = camera.eye, d = camera.ray(column, row);
            double best = std::numeric_limits<double>::infinity();
            const double b = glm::dot(o, d), c = glm::dot(o, o) - r * r, disc = b * b - c;
            if (disc >= 0.0) {
                const double t = -b - std::sqrt(disc);
                if (t > 0.0 && (o + t * d).z >= 0.0) best = t;
            }
            if (d.z < 0.0) {
                const double t = -o.z / d.z;
                const glm::dvec3 p = o + t * d;
                if (p.x * p.x + p.y * p.y >= r * r && t < best) best = t;
            }
            if (std::isfinite(best)) {
                image.hitMm[image.index(column, row)] = o + best * d;
                image.isHit[image.index(column, row)] = 1;
            }
        }
    }
    return image;
}

TEST(PolypDiameter, HemisphereSeenFromAboveIsItsBaseDiameter) {
    const double r = 5.0, distance = 20.0 * r;
    // The half ball spans about a third of the image.
    const Camera camera{{0.0, 0.0, distance}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, glm::degrees(3.0 * 2.0 * std::atan(r / distance)), 256};
    const colon::HitImage image = castHemisphere(camera, r);
    const colon::PatchDiameter patch = colon::polypDiameter(image, 128, 128);
    const double footprint = camera.footprint(distance);
    EXPECT_NEAR(patch.diameterMm, 2.0 * r, 0.5 * footprint);
    EXPECT_NEAR(glm::length(patch.end0Mm - patch.end1Mm), patch.diameterMm, 1e-9);
    EXPECT_NEAR(patch.sphereRadiusMm, r, 0.01 * r);
    // The patch is the visible cap, not the plane: about the disc's pixels.
    const double discPixels = 3.14159265 * std::pow(r / footprint, 2.0);
    EXPECT_NEAR(patch.pixelCount, discPixels, 0.05 * discPixels);
}

TEST(PolypDiameter, HemisphereSeenObliquelyIsItsBaseDiameter) {
    const double r = 2.0, distance = 20.0 * r;
    const double tilt = glm::radians(50.0);
    const glm::dvec3 eye = distance * glm::dvec3(std::sin(tilt), 0.3 * std::sin(tilt), std::cos(tilt));
    const Camera camera{eye, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, glm::degrees(3.0 * 2.0 * std::atan(r / distance)), 256};
    const colon::HitImage image = castHemisphere(camera, r);
    // Away from the centre too: the seed is any pixel on the polyp.
    const colon::PatchDiameter patch = colon::polypDiameter(image, 120, 131);
    EXPECT_NEAR(patch.diameterMm, 2.0 * r, 0.5 * camera.footprint(distance));
    EXPECT_GT(patch.pixelCount, 1000);
    // A pixel on the plane beside it is no protrusion: refused, not measured as the polyp.
    ASSERT_TRUE(image.hitAt(5, 5));
    try {
        colon::polypDiameter(image, 5, 5);
        FAIL() << "the plane measured";
    } catch (const colon::ColonError& e) {
        EXPECT_NE(std::string(e.what()).find("no protrusion there"), std::string::npos) << e.what();
    }
}

TEST(SurfaceDistance, IsTheDistanceBetweenTheTwoHits) {
    const double r = 3.0;
    const Camera camera{{30.0, -20.0, 40.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 30.0, 128};
    const colon::HitImage image = castHemisphere(camera, r);
    // The analytic hits, recomputed here: pixel (64, 64) looks at the half ball, (10, 120) at the plane.
    const glm::dvec3 onBall = [&] {
        const glm::dvec3 d = camera.ray(64, 64), o = camera.eye;
        const double b = glm::dot(o, d);
        return o + (-b - std::sqrt(b * b - glm::dot(o, o) + r * r)) * d;
    }();
    const glm::dvec3 onPlane = [&] {
        const glm::dvec3 d = camera.ray(10, 120);
        return camera.eye + (-camera.eye.z / d.z) * d;
    }();
    EXPECT_NEAR(glm::length(onBall) , r, 1e-9);
    EXPECT_NEAR(colon::surfaceDistanceMm(image, 64, 64, 10, 120), glm::length(onBall - onPlane), 1e-9);
    EXPECT_EQ(colon::surfaceDistanceMm(image, 7, 9, 7, 9), 0.0);
    try {
        colon::surfaceDistanceMm(image, 64, 64, 128, 3);
        FAIL() << "outside the image";
    } catch (const colon::ColonError& e) {
        EXPECT_NE(std::string(e.what()).find("pixel (128, 3) lies outside the 128x128"), std::string::npos) << e.what();
    }
    colon::HitImage holed = image;
    holed.isHit[holed.index(10, 120)] = 0;
    try {
        colon::surfaceDistanceMm(holed, 64, 64, 10, 120);
        FAIL() << "a miss";
    } catch (const colon::ColonError& e) {
        EXPECT_NE(std::string(e.what()).find("pixel (10, 120) is a miss"), std::string::npos) << e.what();
    }
    EXPECT_THROW(colon::polypDiameter(holed, 10, 120), colon::ColonError);
}

// ---- reading the two forms -------------------------------------------------------------

fs::path tmp(const std::string& name) {
    const fs::path folder = fs::path(CVC_TEST_TMP_DIR) / "hit_image";
    fs::create_directories(folder);
    return folder / name;
}

std::string header(int components, int width, int height, const std::string& encoding,
                   const std::string& type = "float") {
    return "NRRD0004\n# test\ntype: " + type + "\ndimension: 3\nsizes: " + std::to_string(components) + " " +
           std::to_string(width) + " " + std::to_string(height) + "\nkinds: " + std::to_string(components) +
           "-vector domain domain\nendian: little\nencoding: " + encoding + "\n\n";
}

std::string bytesOf(const std::vector<float>& values) {
    return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
}

std::string gzip(const std::string& bytes) {
    z_stream stream{};
    EXPECT_EQ(deflateInit2(&stream, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
    std::string out(deflateBound(&stream, static_cast<uLong>(bytes.size())), '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = static_cast<uInt>(out.size());
    EXPECT_EQ(deflate(&stream, Z_FINISH), Z_STREAM_END);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
}

fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path path = tmp(name);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    return path;
}

/// A 3 x 2 image: (x, y) hits at (x, 10 y, 0.5) but for pixel (1, 0), a miss.
std::vector<float> pixels(int components) {
    std::vector<float> values;
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 3; ++x) {
            const bool miss = x == 1 && y == 0;
            const float nan = std::numeric_limits<float>::quiet_NaN();
            values.push_back(miss && components == 3 ? nan : static_cast<float>(x));
            values.push_back(miss && components == 3 ? nan : static_cast<float>(10 * y));
            values.push_back(miss && components == 3 ? nan : 0.5f);
            if (components == 4) values.push_back(miss ? 0.0f : 1.0f);
        }
    }
    return values;
}

void expectPixels(const colon::HitImage& image) {
    ASSERT_EQ(image.width, 3);
    ASSERT_EQ(image.height, 2);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 3; ++x) {
            const bool miss = x == 1 && y == 0;
            EXPECT_EQ(image.hitAt(x, y), !miss) << x << "," << y;
            if (!miss) {
                EXPECT_EQ(image.hitMm[image.index(x, y)], glm::dvec3(x, 10 * y, 0.5)) << x << "," << y;
            }
        }
    }
}

TEST(ReadHitImage, ReadsThePinholeAndTheDisplayForms) {
    expectPixels(colon::readHitImage(write("raw4.nrrd", header(4, 3, 2, "raw") + bytesOf(pixels(4))).string()));
    expectPixels(colon::readHitImage(write("gzip3.nrrd", header(3, 3, 2, "gzip") + gzip(bytesOf(pixels(3)))).string()));
}

void expectRefused(const std::string& name, const std::string& bytes, const std::string& words) {
    const fs::path path = write(name, bytes);
    try {
        colon::readHitImage(path.string());
        FAIL() << name << " was read";
    } catch (const colon::ColonError& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << name << ": " << e.what();
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
}

TEST(ReadHitImage, RefusesWhatIsNotAHitImage) {
    const std::string raw = bytesOf(pixels(4));
    const std::string packed = gzip(bytesOf(pixels(3)));
    expectRefused("text.nrrd", "hello, world\n", "no NRRD magic");
    expectRefused("double.nrrd", header(4, 3, 2, "raw", "double") + raw, "type \"double\"");
    expectRefused("two.nrrd", header(2, 3, 2, "raw") + raw, "2 components, expected 3 or 4");
    expectRefused("huge.nrrd", header(4, 20000, 2, "raw") + raw, "width 20000 is outside 1..16384");
    expectRefused("zero.nrrd", header(4, 3, 0, "raw") + raw, "height 0 is outside");
    expectRefused("short_raw.nrrd", header(4, 3, 2, "raw") + raw.substr(0, raw.size() - 5), "truncated");
    expectRefused("long_raw.nrrd", header(4, 3, 2, "raw") + raw + "xx", "the data holds 98 bytes, its sizes say 96");
    expectRefused("short_gzip.nrrd", header(3, 3, 2, "gzip") + packed.substr(0, packed.size() / 2), "truncated");
    expectRefused("big_gzip.nrrd", header(3, 3000, 3000, "gzip") + packed, "truncated");
    expectRefused("bzip.nrrd", header(3, 3, 2, "bzip2") + packed, "encoding \"bzip2\"");
    expectRefused("no_data.nrrd", "NRRD0004\ntype: float\ndimension: 3\nsizes: 4 3 2\n", "truncated");
    std::vector<float> bad = pixels(4);
    bad[4 * 4 + 1] = std::numeric_limits<float>::infinity();  // pixel (1, 1), a hit
    expectRefused("inf.nrrd", header(4, 3, 2, "raw") + bytesOf(bad), "pixel (1, 1) is a hit with a non-finite position");
    std::vector<float> partly = pixels(3);
    partly[3 * 3 + 2] = std::numeric_limits<float>::quiet_NaN();  // pixel (0, 1): x, y given, z NaN
    expectRefused("partly_nan.nrrd", header(3, 3, 2, "gzip") + gzip(bytesOf(partly)), "pixel (0, 1) is a hit with a non-finite");
    try {
        colon::readHitImage(tmp("absent.nrrd").string());
        FAIL();
    } catch (const colon::ColonError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot be read"), std::string::npos);
    }
}

}  // namespace
