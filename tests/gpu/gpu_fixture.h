#pragma once
// Shared fixture of the GPU tests: one Vulkan context per test suite with the validation layer
// on, and any validation warning or error -- during a test or while tearing the context down --
// fails the test. AAMAP_DEVICE picks the device (default: the ContextOptions rule).
#include <cstdint>
#include <cstdlib>
#include <memory>

#include <gtest/gtest.h>

#include "engine/vk/context.h"

namespace aamap::test {

class GpuTest : public ::testing::Test {
public:
    static void SetUpTestSuite() {
        ContextOptions options;
        options.validation = true;
        if (const char* device = std::getenv("AAMAP_DEVICE")) options.device = device;
        context_ = std::make_unique<VulkanContext>(options);
        if (!context_->validationEnabled()) ADD_FAILURE() << "the GPU tests must run with validation";
    }
    static void TearDownTestSuite() {
        const std::uint64_t before = VulkanContext::processValidationMessageCount();
        context_.reset();
        if (VulkanContext::processValidationMessageCount() != before)
            ADD_FAILURE() << "validation messages while destroying the Vulkan context (see the log)";
    }

protected:
    void SetUp() override { messagesAtStart_ = context_->validationMessageCount(); }
    void TearDown() override {
        EXPECT_EQ(context_->validationMessageCount(), messagesAtStart_)
            << "validation warnings/errors during the test (logged above)";
    }
    static VulkanContext& context() { return *context_; }

private:
    static inline std::unique_ptr<VulkanContext> context_;
    std::uint64_t messagesAtStart_ = 0;
};

}  // namespace aamap::test
