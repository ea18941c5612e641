// Tile classes (shaders/wrs_common.h, docs/speed.md "Tiles"), on the CPU with the shared header:
// wherever wrs_tile_class gives a tile a class, every pixel of that tile gets exactly the class's
// levels from the per-pixel path (wrs_foveation_levels of wrs_eccentricity_deg of wrs_pixel_ray),
// so the tiled dispatch cannot change a bit; and the classes do occur.
#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "shaders/wrs_common.h"

namespace wrsfov::gpu {
namespace {

vec3 direction(float azimuthDeg, float elevationDeg) {
    const float a = azimuthDeg * WRS_PI / 180.0f, e = elevationDeg * WRS_PI / 180.0f;
    return normalize(vec3(std::sin(a) * std::cos(e), std::sin(e), -std::cos(a) * std::cos(e)));
}

// A narrow to wide field of view (asymmetric, half-width `half` degrees) at a size that is not a
// multiple of the tile.
struct View {
    float half;
    vec4 fov_tan;
    uvec2 size;
};
View randomView(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float half = 8.0f + 52.0f * u(rng);
    const vec4 fov_tan(std::tan((-half - 6.0f * u(rng)) * WRS_PI / 180.0f), std::tan(half * WRS_PI / 180.0f),
                       std::tan((half + 4.0f * u(rng)) * WRS_PI / 180.0f), std::tan(-half * WRS_PI / 180.0f));
    const uvec2 size(40u + uint(u(rng) * 200.0f), 30u + uint(u(rng) * 170.0f));
    return {half, fov_tan, size};
}

TEST(TileClasses, EveryClassifiedPixelGetsTheClassLevels) {
    std::mt19937 rng(20261123);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::array<uint64_t, WRS_TILE_CLASSES> tiles{};
    uint64_t pixels = 0;
    for (int view = 0; view < 120; ++view) {
        const auto [half, fov_tan, size] = randomView(rng);
        const vec4 tile = wrs_tile_geometry(size, fov_tan);
        const vec3 gaze = direction(-half + 2.0f * half * u(rng), -half + 2.0f * half * u(rng));
        const float foveaDeg[] = {2.0f, 5.0f, 7.5f, 10.0f, 20.0f};
        const float r_f = 0.5f * foveaDeg[view % 5];
        const float r_m = 7.5f;
        for (uint mode : {WRS_FOV_MIP, WRS_FOV_GAUSS, WRS_FOV_NONE}) {
            const uvec2 count = (size + uvec2(WRS_TILE - 1u)) / WRS_TILE;
            for (uint ty = 0; ty < count.y; ++ty)
                for (uint tx = 0; tx < count.x; ++tx) {
                    const uint cls = wrs_tile_class(mode, uvec2(tx, ty), size, fov_tan, tile, gaze, r_f, r_m);
                    ++tiles[cls];
                    if (mode == WRS_FOV_NONE) {
                        ASSERT_EQ(cls, WRS_TILE_ANY);
                    }
                    if (cls == WRS_TILE_ANY) continue;
                    const vec3 want = wrs_tile_levels(cls);
                    for (uint y = ty * WRS_TILE; y < std::min(size.y, (ty + 1u) * WRS_TILE); ++y)
                        for (uint x = tx * WRS_TILE; x < std::min(size.x, (tx + 1u) * WRS_TILE); ++x) {
                            const float e = wrs_eccentricity_deg(wrs_pixel_ray(x, y, size.x, size.y, fov_tan), gaze);
                            const vec3 lv = wrs_foveation_levels(mode, e, r_f, r_m);
                            ++pixels;
                            ASSERT_TRUE(lv == want) << "view " << view << " mode " << mode << " tile " << tx << ","
                                                    << ty << " class " << cls << " pixel " << x << "," << y
                                                    << " e " << e << " r_f " << r_f << " levels " << lv.x << ","
                                                    << lv.y << "," << lv.z;
                        }
                }
        }
    }
    for (uint c = 0; c < WRS_TILE_CLASSES; ++c) EXPECT_GT(tiles[c], 50u) << "class " << c << " never occurred";
    std::printf("tiles per class (any, fovea, mid, far): %llu %llu %llu %llu; %llu classified pixels checked\n",
                (unsigned long long)tiles[0], (unsigned long long)tiles[1], (unsigned long long)tiles[2],
                (unsigned long long)tiles[3], (unsigned long long)pixels);
}

// wrs_tile_geometry's rho bounds the angle from a tile's centre to every point of it (the central
// projection onto the sphere shrinks lengths): checked at every corner and pixel centre of every tile
// of wide, asymmetric views, and it is tight on the axis (within 1 % of the exact half-diagonal angle).
TEST(TileClasses, RhoBoundsTheAngleAcrossATile) {
    std::mt19937 rng(20261126);
    double worst = 0.0, onAxis = 0.0;
    for (int view = 0; view < 40; ++view) {
        const auto [half, fov_tan, size] = randomView(rng);
        const vec4 tile = wrs_tile_geometry(size, fov_tan);
        ASSERT_GT(tile.z, 0.0f);
        const uvec2 count = (size + uvec2(WRS_TILE - 1u)) / WRS_TILE;
        for (uint ty = 0; ty < count.y; ++ty)
            for (uint tx = 0; tx < count.x; ++tx) {
                const vec2 a = vec2(uvec2(tx, ty) * WRS_TILE);
                const vec2 b = vec2(min(uvec2(tx + 1u, ty + 1u) * WRS_TILE, size));
                const vec3 c = wrs_image_point_ray(0.5f * (a + b), size, fov_tan);
                double rho = 0.0;
                for (float y = a.y; y <= b.y; y += 0.5f)
                    for (float x = a.x; x <= b.x; x += 0.5f)
                        rho = std::max(
                            rho, double(wrs_eccentricity_deg(wrs_image_point_ray(vec2(x, y), size, fov_tan), c)));
                worst = std::max(worst, rho / tile.z);
                if (c.z < -0.9999f && b.x - a.x == float(WRS_TILE) && b.y - a.y == float(WRS_TILE))
                    onAxis = std::max(onAxis, rho / tile.z);
            }
    }
    EXPECT_LE(worst, 1.0 + 1e-4) << "rho is not a bound";
    EXPECT_GT(onAxis, 0.99) << "rho is loose on the axis";
    std::printf("largest angle across a tile / rho: %.5f (on the axis %.5f)\n", worst, onAxis);
}

TEST(TileClasses, RangesOnTheBoundaries) {
    // mip, fovea 5 degrees (r_f 2.5), mid-periphery to 7.5: the blends (2.5, 3.5) and (7.5, 8.5) are never a class.
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 0.0f, 2.5f, 2.5f, 7.5f), WRS_TILE_FOVEA);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 0.0f, 2.51f, 2.5f, 7.5f), WRS_TILE_ANY);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 3.5f, 7.5f, 2.5f, 7.5f), WRS_TILE_MID);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 3.49f, 7.5f, 2.5f, 7.5f), WRS_TILE_ANY);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 3.5f, 7.51f, 2.5f, 7.5f), WRS_TILE_ANY);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 8.5f, 90.0f, 2.5f, 7.5f), WRS_TILE_FAR);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 8.49f, 90.0f, 2.5f, 7.5f), WRS_TILE_ANY);
    // A 20-degree fovea reaches past the mid-periphery: level 0, a blend to 4, then 4.
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 11.0f, 90.0f, 10.0f, 7.5f), WRS_TILE_FAR);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_MIP, 10.9f, 90.0f, 10.0f, 7.5f), WRS_TILE_ANY);
    // gauss: level 4 from 5 degrees past the mid-periphery.
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_GAUSS, 12.5f, 90.0f, 2.5f, 7.5f), WRS_TILE_FAR);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_GAUSS, 12.4f, 90.0f, 2.5f, 7.5f), WRS_TILE_ANY);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_GAUSS, 4.0f, 7.0f, 2.5f, 7.5f), WRS_TILE_ANY);
    EXPECT_EQ(wrs_tile_class_of_range(WRS_FOV_NONE, 0.0f, 1.0f, 2.5f, 7.5f), WRS_TILE_ANY);
    // The levels of each class are those of the per-pixel path inside it.
    EXPECT_TRUE(wrs_foveation_levels(WRS_FOV_MIP, 5.0f, 2.5f, 7.5f) == wrs_tile_levels(WRS_TILE_MID));
    EXPECT_TRUE(wrs_foveation_levels(WRS_FOV_GAUSS, 30.0f, 2.5f, 7.5f) == wrs_tile_levels(WRS_TILE_FAR));
}

}  // namespace
}  // namespace wrsfov::gpu
