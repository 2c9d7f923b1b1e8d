/* sandbox_new.cpp - operator new for fuzz_import: past a size it throws std::bad_alloc, as it does in
 * lucent-import under the sandbox's address-space limit, where AddressSanitizer would end the run. */
#include <cstdlib>
#include <new>

namespace {

/* lucentd gives lucent-import 2 GiB of address space (import-memory-bytes), code and stacks included.
 * A single allocation past 1 GiB fails here as one past RLIMIT_AS fails there: assimp sizes arrays by
 * counts in the file (a PLY list of 2^32 - 1 indices asks for 32 GB), gets bad_alloc and refuses the
 * file, where AddressSanitizer's own operator new would report it and abort. What accumulates is
 * bounded by run.sh's -rss_limit_mb instead. */
constexpr std::size_t LARGEST = std::size_t{1} << 30;

void *allocate_or_null(std::size_t size) noexcept
{
    return size <= LARGEST ? std::malloc(size ? size : 1) : nullptr;
}

void *allocate(std::size_t size)
{
    void *p = allocate_or_null(size);
    if (!p)
        throw std::bad_alloc();
    return p;
}

} // namespace

/* Every replaceable form but the aligned ones, which nothing here uses: defining a form pulls in
 * none of AddressSanitizer's (the linker would then see two of each). malloc and free underneath
 * are still AddressSanitizer's, so overflows and use after free are caught as before. */
void *operator new(std::size_t size) { return allocate(size); }
void *operator new[](std::size_t size) { return allocate(size); }
void *operator new(std::size_t size, const std::nothrow_t &) noexcept { return allocate_or_null(size); }
void *operator new[](std::size_t size, const std::nothrow_t &) noexcept { return allocate_or_null(size); }
void operator delete(void *p) noexcept { std::free(p); }
void operator delete[](void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t) noexcept { std::free(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { std::free(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { std::free(p); }
