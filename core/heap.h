#pragma once
// Process-wide allocator policy for the executables (call once, first thing in main).

namespace aamap {

// Keeps freed memory in the heap for reuse instead of handing it back to the kernel. The
// Snapshot and the tracer allocate images of the same few MiB every frame; with glibc's defaults
// each is mmapped or trimmed away when freed and page-faulted back in, zero-filled, next frame
// (page faults and read-back time with and without it: docs/results.md). Blocks over 32 MiB are
// still mmapped. No effect off glibc.
void keepFreedMemoryForReuse();

}  // namespace aamap
