// The portable sin, cos and exp (plimsoll_eval/portable_math.hpp, musl's code compiled in): the
// runtime's waves take them on every platform, so they must be as good as a C library's. Checked
// against the C library's own functions (glibc's, within one unit in the last place of the true
// value) over every range the code reduces differently: each result within one unit in the last
// place of the library's, the exact values and the special cases IEEE 754 and C fix, and the
// symmetries that make a mirrored hull's forces mirror.
//
// Its own executable: the definitions below are the portable ones only where
// PLIMSOLL_EVAL_PORTABLE_MATH is defined, and every other test file sees the C library's.
#include "plimsoll_eval/portable_math.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#if !defined(PLIMSOLL_EVAL_PORTABLE_MATH)
#error "tests/eval/test_portable_math.cpp is built with PLIMSOLL_EVAL_PORTABLE_MATH"
#endif

namespace {

namespace pm = plimsoll_eval::math;

/// Units in the last place between a and b (both finite, of one sign or zero).
std::int64_t ulpsApart(double a, double b) {
    auto ordered = [](double x) {
        std::int64_t i;
        std::memcpy(&i, &x, sizeof i);
        return i < 0 ? std::numeric_limits<std::int64_t>::min() - i : i;
    };
    const std::int64_t d = ordered(a) - ordered(b);
    return d < 0 ? -d : d;
}

struct Range {
    double low, high;
};

/// The largest distance from the C library over `count` arguments drawn uniformly in each range.
template <class Portable, class Library>
std::int64_t worstUlps(Portable portable, Library library, std::initializer_list<Range> ranges,
                       int count, double& worstAt) {
    std::mt19937_64 random(20261207);
    std::int64_t worst = 0;
    for (const Range& r : ranges) {
        std::uniform_real_distribution<double> pick(r.low, r.high);
        for (int i = 0; i < count; ++i) {
            const double x = pick(random);
            const std::int64_t d = ulpsApart(portable(x), library(x));
            if (d > worst) worst = d, worstAt = x;
        }
    }
    return worst;
}

TEST(PortableMath, SineAndCosineAreWithinOneUlpOfTheLibraryOnEveryReduction) {
    // |x| < pi/4 (no reduction), < 9 pi/4 (the small multiples), < 2^20 pi/2 (the medium
    // reduction), beyond (the large, multi-word reduction) up to 1e300.
    const std::initializer_list<Range> ranges = {
        {-0.785, 0.785}, {-7.0, 7.0},      {-200.0, 200.0},   {-1.0e6, 1.0e6},
        {1.0e7, 1.0e9},  {1.0e20, 1.0e22}, {1.0e290, 1.0e300}};
    double at = 0;
    EXPECT_LE(worstUlps([](double x) { return pm::sin(x); }, [](double x) { return std::sin(x); },
                        ranges, 40000, at),
              1)
        << "sin at " << at;
    EXPECT_LE(worstUlps([](double x) { return pm::cos(x); }, [](double x) { return std::cos(x); },
                        ranges, 40000, at),
              1)
        << "cos at " << at;
}

TEST(PortableMath, ExponentialIsWithinOneUlpOfTheLibraryFromUnderflowToOverflow) {
    const std::initializer_list<Range> ranges = {
        {-1.0e-8, 1.0e-8}, {-1.0, 1.0}, {-30.0, 0.0}, {-700.0, 700.0}, {-745.0, -708.0}};
    double at = 0;
    EXPECT_LE(worstUlps([](double x) { return pm::exp(x); }, [](double x) { return std::exp(x); },
                        ranges, 40000, at),
              1)
        << "exp at " << at;
}

TEST(PortableMath, ExactValuesAndSpecialCasesAreIeeeAndCs) {
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(pm::sin(0.0), 0.0);
    EXPECT_TRUE(std::signbit(pm::sin(-0.0)));
    EXPECT_EQ(pm::cos(0.0), 1.0);
    EXPECT_EQ(pm::cos(-0.0), 1.0);
    EXPECT_EQ(pm::exp(0.0), 1.0);
    EXPECT_EQ(pm::exp(-0.0), 1.0);
    // Tiny arguments: sin x = x and cos x = 1, to the bit.
    EXPECT_EQ(pm::sin(1.0e-300), 1.0e-300);
    EXPECT_EQ(pm::cos(1.0e-300), 1.0);
    EXPECT_TRUE(std::isnan(pm::sin(inf)));
    EXPECT_TRUE(std::isnan(pm::cos(-inf)));
    EXPECT_TRUE(std::isnan(pm::sin(nan)));
    EXPECT_TRUE(std::isnan(pm::exp(nan)));
    EXPECT_EQ(pm::exp(inf), inf);
    EXPECT_EQ(pm::exp(-inf), 0.0);
    EXPECT_EQ(pm::exp(710.0), inf);   // beyond DBL_MAX
    EXPECT_EQ(pm::exp(-746.0), 0.0);  // below the smallest subnormal
    EXPECT_GT(pm::exp(-744.0), 0.0);  // a subnormal, not flushed
}

TEST(PortableMath, SineIsOddAndCosineEvenToTheBit) {
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> pick(-1.0e4, 1.0e4);
    for (int i = 0; i < 100000; ++i) {
        const double x = pick(random);
        ASSERT_EQ(pm::sin(-x), -pm::sin(x)) << x;
        ASSERT_EQ(pm::cos(-x), pm::cos(x)) << x;
    }
}

}  // namespace
