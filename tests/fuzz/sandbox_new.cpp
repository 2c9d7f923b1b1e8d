/* sandbox_new.cpp - operator new for fuzz_import: past a memory budget it throws std::bad_alloc, as it does
 * in lucent-import under the sandbox's address-space limit, where AddressSanitizer would end the run. */
#include <malloc.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

/* lucentd gives lucent-import 2 GiB of address space (import-memory-bytes), code and stacks included;
 * 1 GiB of live allocations stands in for it, leaving AddressSanitizer's shadow and quarantine room
 * under run.sh's -rss_limit_mb 2048. An allocation past it fails as one past RLIMIT_AS does: assimp
 * sizes arrays by counts in the file (a PLY list of 2^32 - 1 indices asks for 32 GB), gets bad_alloc
 * and refuses the file. AddressSanitizer's own operator new reports the failure and aborts instead. */
constexpr std::size_t BUDGET = std::size_t{1} << 30;
std::atomic<std::size_t> live{0};

void *allocate(std::size_t size)
{
    if (size > BUDGET - live.load())
        throw std::bad_alloc();
    void *p = std::malloc(size ? size : 1);
    if (!p)
        throw std::bad_alloc();
    live += malloc_usable_size(p);
    return p;
}

void *allocate_or_null(std::size_t size) noexcept
{
    try {
        return allocate(size);
    } catch (const std::bad_alloc &) {
        return nullptr;
    }
}

void release(void *p) noexcept
{
    if (!p)
        return;
    live -= malloc_usable_size(p);
    std::free(p);
}

} // namespace

/* Every replaceable form but the aligned ones, which nothing here uses: defining a form pulls in
 * none of AddressSanitizer's (the linker would then see two of each). malloc and free underneath
 * are still AddressSanitizer's, so overflows and use after free are caught as before. */
void *operator new(std::size_t size) { return allocate(size); }
void *operator new[](std::size_t size) { return allocate(size); }
void *operator new(std::size_t size, const std::nothrow_t &) noexcept { return allocate_or_null(size); }
void *operator new[](std::size_t size, const std::nothrow_t &) noexcept { return allocate_or_null(size); }
void operator delete(void *p) noexcept { release(p); }
void operator delete[](void *p) noexcept { release(p); }
void operator delete(void *p, std::size_t) noexcept { release(p); }
void operator delete[](void *p, std::size_t) noexcept { release(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { release(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { release(p); }
