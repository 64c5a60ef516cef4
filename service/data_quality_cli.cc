#include "service/data_quality_cli.h"

#if defined(__GLIBC__)
#include <sys/mman.h>
#include <unistd.h>

#include <malloc.h>
#endif

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <utility>

#include "core/dataset/dataset_io.h"

namespace rollwear::cli {
namespace {

// A file tool reads a dataset into buffers of tens of MB (a paper-size
// coils.csv: 10 MB of text, 12 MB of field spans, 10 MB of passes) and
// faults every 4 KiB page of them in: 12,000 page faults, a fifth of a
// paper-size `calibrate` (perf). Two glibc settings make that cheap, for
// the short-lived file tools only (the daemon keeps glibc's defaults):
//  - blocks up to 32 MiB come from the heap and freed memory stays there
//    for reuse (mmap threshold 32 MiB, the most glibc accepts on 64 bits,
//    HEAP_MAX_SIZE / 2; trim threshold 1 GiB; by default glibc maps each
//    block over 128 KiB on its own and unmaps it on free, so the next
//    block faults its pages in again);
//  - the heap grows in one step of 256 MiB of address space (M_TOP_PAD;
//    pages are backed only when touched), and that step, read as the
//    program break before and after it, is advised for transparent huge
//    pages (madvise(MADV_HUGEPAGE); the kernel's THP setting on Debian 12
//    is "madvise"), so the reader's buffers fault in 2 MiB at a time.
// Where a setting is refused, THP is off or the heap is not the program
// break (ASan and TSan allocate elsewhere), nothing is advised and the
// tool runs as before. Measured (docs/performance.md): a paper-size
// `calibrate` 79 -> 62 ms wall (median of 21), page faults 12,166 -> 1,512,
// peak RSS 61 -> 63 MB (these two steps; 56 MB before either).
void ReuseFreedMemory() {
#if defined(__GLIBC__)
  static const bool once = [] {
    constexpr int kMmapThresholdBytes = 32 << 20;
    constexpr int kTrimThresholdBytes = 1 << 30;
    constexpr int kTopPadBytes = 256 << 20;
    if (mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes) != 1 ||
        mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes) != 1 ||
        mallopt(M_TOP_PAD, kTopPadBytes) != 1) {
      return false;
    }
    // One block under the threshold grows the heap by the pad.
    const auto before = reinterpret_cast<uintptr_t>(sbrk(0));
    void* first = std::malloc(size_t{1} << 20);
    const auto after = reinterpret_cast<uintptr_t>(sbrk(0));
    constexpr uintptr_t kHugePage = uintptr_t{2} << 20;
    const uintptr_t from = (before + kHugePage - 1) & ~(kHugePage - 1);
    if (first != nullptr && after > from) {
      madvise(reinterpret_cast<void*>(from), after - from, MADV_HUGEPAGE);
    }
    std::free(first);
    return true;
  }();
  (void)once;
#endif
}

}  // namespace

int DatasetReadOptionsFromEnvironment(const char* tool,
                                      DatasetReadOptions* out) {
  const char* text = std::getenv("ROLLWEAR_UTC_OFFSET");
  if (text == nullptr || *text == '\0') return 0;
  int offset_s = 0;
  if (!ParseUtcOffset(text, &offset_s)) {
    std::fprintf(stderr,
                 "rollwear %s: ROLLWEAR_UTC_OFFSET '%s' is not a UTC offset "
                 "(want +HH:MM, -HH:MM or Z, e.g. +01:00)\n",
                 tool, text);
    return 2;
  }
  out->local_utc_offset_s = offset_s;
  return 0;
}

int ReadDatasetForTool(const char* tool, const std::string& dir, Dataset* out) {
  ReuseFreedMemory();
  DatasetReadOptions options;
  if (int code = DatasetReadOptionsFromEnvironment(tool, &options)) return code;
  StatusOr<Dataset> data = ReadDataset(dir, nullptr, options);
  if (!data.ok()) {
    std::fprintf(stderr, "rollwear %s: %s\n", tool,
                 data.status().message().c_str());
    return 1;
  }
  *out = *std::move(data);
  return 0;
}

int ReadCheckedDataset(const char* tool, const std::string& dir, bool strict,
                       CheckedDataset* out, Keep keep) {
  ReuseFreedMemory();
  DatasetReadOptions options;
  if (int code = DatasetReadOptionsFromEnvironment(tool, &options)) return code;
  DatasetLines& lines = out->lines;
  StatusOr<Dataset> data = ReadDataset(dir, &lines, options);
  if (!data.ok()) {
    std::fprintf(stderr, "rollwear %s: %s\n", tool,
                 data.status().message().c_str());
    return 1;
  }
  out->quality = AssessDataQuality(*data, &lines);
  std::printf("%s", DataQualitySummary(out->quality).c_str());
  std::fflush(stdout);
  if (strict && !out->quality.issues.empty()) {
    const DataQualityIssue& first = out->quality.issues.front();
    std::fprintf(stderr,
                 "rollwear %s: --strict: %zu data-quality warning(s), first "
                 "%s %s: %s\n",
                 tool, out->quality.issues.size(), first.Location().c_str(),
                 first.where.c_str(), first.reason.c_str());
    return 1;
  }
  if (keep == Keep::kAll) {
    out->all = *std::move(data);
  } else {
    RemoveSuspects(out->quality, &*data);
    out->fit = *std::move(data);
  }
  return 0;
}

void PrintSuspectedOutliers(const std::vector<SuspectedOutlier>& outliers,
                            int max_listed) {
  if (outliers.empty()) {
    std::printf("suspected outliers: none (no reading more than %.0f sd off)\n",
                kOutlierSigmas);
    return;
  }
  std::printf(
      "suspected outliers: %zu reading(s) more than %.0f sd off the fit "
      "(kept at Huber weight, robust loss)%s\n",
      outliers.size(), kOutlierSigmas,
      static_cast<int>(outliers.size()) > max_listed ? ", the largest:" : ":");
  for (size_t i = 0; i < outliers.size() && static_cast<int>(i) < max_listed;
       ++i) {
    std::printf("  %s\n", OutlierLine(outliers[i]).c_str());
  }
}

bool SpoilsCalibration(const DataQuality& quality) {
  return quality.Count(DataQualityKind::kNoPasses) > 0;
}

}  // namespace rollwear::cli

namespace rollwear::cli {

int ApplySplitFile(const char* tool, const std::string& file,
                   CheckedDataset* out, std::optional<CampaignSplit>* split,
                   SplitDataset* applied) {
  if (file.empty()) return 0;
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "rollwear %s: cannot read --split %s\n", tool, file.c_str());
    return 1;
  }
  std::ostringstream text;
  text << in.rdbuf();
  StatusOr<std::vector<SplitRow>> rows = ParseSplitCsv(text.str(), file);
  StatusOr<SplitDataset> s =
      rows.ok() ? ApplySplit(out->fit, *rows) : StatusOr<SplitDataset>(rows.status());
  if (!s.ok()) {
    std::fprintf(stderr, "rollwear %s: --split: %s\n", tool, s.status().message().c_str());
    return 1;
  }
  std::printf("%s\n", DescribeSplit(*s, file).c_str());
  *split = s->split;
  out->fit = s->data;
  if (applied != nullptr) *applied = std::move(*s);
  return 0;
}

}  // namespace rollwear::cli
