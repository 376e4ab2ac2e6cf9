// bench_filter: the aamap filters on the CPU and through Vulkan, against a copy of the same image
// (the paper's Figure 4). Progress on stderr, the tables on stdout, the rows in --csv.
//   bench_filter [--sizes 256,512,...] [--stages laplacian,blur] [--repeats 7] [--warmup 2]
//                [--device NAME] [--validation] [--csv FILE] [--smoke] [--cpu-only]
// Environment: AAMAP_DEVICE sets the default --device, AAMAP_VALIDATION=1 turns on --validation.
// Exit codes: 0 success, 1 environment error, 2 bad options, 3 validation messages, 4 disagreement.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <malloc.h>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "core/atomic_file.h"
#include "engine/vk/context.h"
#include "filter_bench.h"
#include "report.h"

namespace {

constexpr double kTolerance = 1e-5;  // GPU vs the CPU reference (the tests in tests/gpu use the same)

std::string envString(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

bool envFlag(const char* name) {
    const std::string v = envString(name);
    return v == "1" || v == "true" || v == "on" || v == "yes" || v == "TRUE" || v == "ON" || v == "YES";
}

int fail(int code, const std::string& message) {
    std::fflush(stdout);
    fmt::print(stderr, "bench_filter: error: {}\n", message);
    return code;
}

// The agreement check: parallel bit-identical to scalar, GPU within kTolerance.
int checkAgreement(const aamap::bench::FilterBenchResult& result) {
    int bad = 0;
    for (const auto& row : result.rows) {
        if (row.stage == "copy") continue;
        const double limit = row.impl.rfind("cpu_parallel", 0) == 0 ? 0.0 : kTolerance;
        if (!(row.maxAbsDiff <= limit)) {
            fmt::print(stderr, "disagreement: {} {} {}x{}: max |diff| {} > {}\n", row.stage, row.impl, row.width,
                       row.height, row.maxAbsDiff, limit);
            ++bad;
        }
    }
    return bad;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"aamap filter benchmark: CPU (scalar, TBB-parallel) vs Vulkan compute, against a copy"};
    aamap::bench::FilterBenchOptions options;
    aamap::ContextOptions contextOptions;
    contextOptions.device = envString("AAMAP_DEVICE");
    contextOptions.validation = envFlag("AAMAP_VALIDATION");
    std::string csv;
    bool smoke = false, cpuOnly = false, freshAlloc = false;
    app.add_option("--sizes", options.sizes, "square image sizes, comma-separated")->delimiter(',');
    app.add_option("--stages", options.stages, "stages to time")
        ->delimiter(',')
        ->check(CLI::IsMember({"laplacian", "blur"}));
    app.add_option("--repeats", options.repeats, "timed runs per measurement (median, min, max reported)");
    app.add_option("--warmup", options.warmup, "untimed runs first");
    app.add_option("--blur-radius", options.blurRadius, "box blur radius");
    app.add_option("--device", contextOptions.device, "Vulkan device index or name substring (default $AAMAP_DEVICE)");
    app.add_flag("--validation", contextOptions.validation, "enable the Vulkan validation layer (or AAMAP_VALIDATION=1)");
    app.add_option("--csv", csv, "write the rows to this CSV file (atomically)");
    app.add_flag("--smoke", smoke,
                 "CI check: tiny sizes, fails on any disagreement, a missing GPU or a validation message");
    app.add_flag("--cpu-only", cpuOnly, "skip the Vulkan rows");
    app.add_flag("--fresh-alloc", freshAlloc,
                 "keep glibc's default of mmap-ing every block over 32 MiB afresh (page faults in every call)");
    CLI11_PARSE(app, argc, argv);
    if (!freshAlloc) {
        // The steady state of a long-running process: the CPU filters return a new image per call,
        // and glibc would mmap (and page-fault) every block over 32 MiB afresh; from the heap, freed
        // images are reused. The serial zero-fill of each new image stays in the timings.
        mallopt(M_MMAP_MAX, 0);
        mallopt(M_TRIM_THRESHOLD, 1 << 30);
    }
    if (smoke) {
        if (cpuOnly) return fail(2, "--smoke needs the GPU rows; drop --cpu-only");
        options.sizes = {37, 64};  // 37: not a multiple of the 16x16 workgroup nor of the SIMD width
        options.repeats = 2;
        options.warmup = 1;
    }

    try {
        std::unique_ptr<aamap::VulkanContext> context;
        if (!cpuOnly) {
            try {
                context = std::make_unique<aamap::VulkanContext>(contextOptions);
            } catch (const std::exception& e) {
                if (smoke) return fail(1, fmt::format("no usable Vulkan device: {}", e.what()));
                fmt::print(stderr, "bench_filter: no usable Vulkan device ({}); CPU rows only\n", e.what());
            }
            if (smoke && !context->validationEnabled())
                return fail(1, "--smoke needs the validation layer (set AAMAP_VALIDATION=1 or --validation)");
        }
        const auto progress = [](const std::string& line) { fmt::print(stderr, "{}\n", line); };
        const auto result = aamap::bench::runFilterBench(context.get(), options, progress);
        context.reset();  // leaks are reported while the context is destroyed: count them too

        std::printf("%s", aamap::bench::filterBenchTable(result, options).c_str());
        if (!csv.empty()) {
            aamap::writeTextAtomically(csv, aamap::bench::filterBenchCsv(result));
            fmt::print(stderr, "wrote {}\n", csv);
        }
        const auto messages = aamap::VulkanContext::processValidationMessageCount();
        std::printf("validation messages: %llu\n", static_cast<unsigned long long>(messages));
        if (messages > 0) return fail(3, fmt::format("{} Vulkan validation messages (see the log)", messages));
        if (const int bad = checkAgreement(result)) return fail(4, fmt::format("{} rows disagree with the reference", bad));
        std::printf("agreement: all implementations within %.0e of the scalar reference (CPU parallel bit-identical)\n",
                    kTolerance);
    } catch (const std::invalid_argument& e) {
        return fail(2, e.what());
    } catch (const std::exception& e) {
        return fail(1, e.what());
    }
    return 0;
}
