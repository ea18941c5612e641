// docs/bad-input.md, "Device faults": the WRSFOV_FAULT values vk::FaultInjection::parse takes and
// refuses (a refused value makes vk::Context::create fail with the same message).
#include <gtest/gtest.h>

#include <string>

#include "compositor/vk_context.h"

namespace wrsfov::vk {
namespace {

TEST(FaultSpec, ParsesEveryKind) {
    auto a = FaultInjection::parse("alloc:3");
    ASSERT_TRUE(a.ok()) << a.error().message;
    EXPECT_EQ(a->failAllocation, 3u);
    EXPECT_EQ(a->loseDevice, 0u);
    auto b = FaultInjection::parse("lost:1,alloc:7");
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(b->failAllocation, 7u);
    EXPECT_EQ(b->loseDevice, 1u);
    auto c = FaultInjection::parse("lost:4294967295");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->loseDevice, 4294967295u);
    auto d = FaultInjection::parse("pipeline:2,alloc:5");
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d->failPipeline, 2u);
    EXPECT_EQ(d->failAllocation, 5u);
    EXPECT_EQ(d->loseDevice, 0u);
    EXPECT_EQ(b->failPipeline, 0u);
    auto e = FaultInjection::parse("object:9");
    ASSERT_TRUE(e.ok()) << e.error().message;
    EXPECT_EQ(e->failObject, 9u);
    EXPECT_EQ(d->failObject, 0u);
}

struct Spec {
    const char* name;
    const char* value;
};
void PrintTo(const Spec& s, std::ostream* os) { *os << "'" << s.value << "'"; }

class Refused : public ::testing::TestWithParam<Spec> {};

TEST_P(Refused, Row) {
    const std::string spec = GetParam().value;
    auto r = FaultInjection::parse(spec);
    ASSERT_FALSE(r.ok()) << "'" << spec << "' was taken";
    EXPECT_NE(r.error().message.find("WRSFOV_FAULT='" + spec + "'"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("alloc:N, lost:N, pipeline:N and/or object:N"), std::string::npos) << r.error().message;
}

INSTANTIATE_TEST_SUITE_P(FaultSpec, Refused,
                         ::testing::Values(Spec{"empty", ""}, Spec{"no_count", "alloc"}, Spec{"empty_count", "alloc:"},
                                           Spec{"zero", "alloc:0"}, Spec{"negative", "alloc:-1"},
                                           Spec{"plus_sign", "alloc:+2"}, Spec{"text", "alloc:x"},
                                           Spec{"fraction", "alloc:2.5"}, Spec{"above_32_bits", "alloc:4294967296"},
                                           Spec{"huge", "alloc:99999999999999999999"}, Spec{"unknown_kind", "boom:1"},
                                           Spec{"trailing_comma", "alloc:1,"}, Spec{"leading_comma", ",alloc:1"},
                                           Spec{"wrong_separator", "alloc:1;lost:2"}, Spec{"upper_case", "ALLOC:1"},
                                           Spec{"pipeline_zero", "pipeline:0"}, Spec{"pipeline_no_count", "pipeline"},
                                           Spec{"object_negative", "object:-3"}),
                         [](const ::testing::TestParamInfo<Spec>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace wrsfov::vk
