// large_blocks.cc: C++ allocations of 1 MiB or more served from a few
// reused mappings, for the harnesses that run assimp in their process
// (fuzz_mesh, fuzz_obj, fuzz_scenes).
//
// Why: assimp's OBJ reader allocates a 16 MiB stream buffer for every file
// (IOStreamBuffer's cache) and fills it twice. Under AddressSanitizer every
// allocation that large is a fresh mapping, so each input paid 4096 page
// faults and the kernel's zeroing: perf put three quarters of fuzz_obj's
// time there, about 50 inputs a second. A freed large block is kept and
// handed to the next large request that fits, so its pages stay mapped.
//
// LeakSanitizer scans a block while it is handed out (libFuzzer keeps its
// own large tables in such blocks, and the pointers in them must count),
// not while it is kept.
//
// What it gives up: these blocks carry no redzones and are not themselves
// leak-checked. Only assimp's own
// code, which is not instrumented, touches its stream buffers; the arrays
// the project reads out of an aiScene are far smaller and still come from
// the sanitizer's malloc, with redzones. Smaller requests go to malloc
// unchanged, so leaks, overflows and use-after-free there are reported as
// before. Not thread-safe beyond a lock: the harnesses read one file at a
// time.
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <new>
#include <sanitizer/lsan_interface.h>
#include <sys/mman.h>

namespace {

constexpr size_t kLarge = size_t(1) << 20; // requests from this size up are served here
constexpr size_t kHuge = size_t(256) << 20; // and below this one: a bigger one goes to malloc, whose limits
                                            // (libFuzzer's -malloc_limit_mb, the sanitizer's) then apply
constexpr int kKept = 8;                   // freed blocks kept for reuse

struct Block {
    void *base = nullptr;
    size_t bytes = 0; // mapped bytes
    bool live = false;
};
Block blocks[kKept * 2]; // live and kept blocks; a block beyond them is unmapped when freed
std::mutex lock;

void *take(size_t size)
{
    std::lock_guard<std::mutex> hold(lock);
    Block *best = nullptr, *empty = nullptr;
    for (Block &b : blocks) {
        if (!b.base) { if (!empty) empty = &b; continue; }
        if (!b.live && b.bytes >= size && (!best || b.bytes < best->bytes)) best = &b;
    }
    if (best) {
        best->live = true;
        __lsan_register_root_region(best->base, best->bytes);
        return best->base;
    }
    const size_t bytes = (size + 4095) & ~size_t(4095);
    void *p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return nullptr;
    if (empty) {
        *empty = Block{p, bytes, true};
        __lsan_register_root_region(p, bytes);
    }
    else { // every record in use: untracked would leak, so refuse
        munmap(p, bytes);
        return nullptr;
    }
    return p;
}

// Whether p is one of the blocks; if so it is released (kept, or unmapped
// when more than kKept are already kept).
bool give_back(void *p)
{
    std::lock_guard<std::mutex> hold(lock);
    int kept = 0;
    Block *mine = nullptr;
    for (Block &b : blocks) {
        if (b.base == p && b.live) mine = &b;
        else if (b.base && !b.live) kept++;
    }
    if (!mine) return false;
    __lsan_unregister_root_region(mine->base, mine->bytes);
    if (kept < kKept) mine->live = false;
    else {
        munmap(mine->base, mine->bytes);
        *mine = Block{};
    }
    return true;
}

void *allocate(size_t size, bool nothrow)
{
    void *p = size >= kLarge && size < kHuge ? take(size) : malloc(size ? size : 1);
    if (!p && !nothrow) throw std::bad_alloc();
    return p;
}

void release(void *p)
{
    if (p && !give_back(p)) free(p);
}

} // namespace

void *operator new(size_t size) { return allocate(size, false); }
void *operator new[](size_t size) { return allocate(size, false); }
void *operator new(size_t size, const std::nothrow_t &) noexcept { return allocate(size, true); }
void *operator new[](size_t size, const std::nothrow_t &) noexcept { return allocate(size, true); }
void operator delete(void *p) noexcept { release(p); }
void operator delete[](void *p) noexcept { release(p); }
void operator delete(void *p, size_t) noexcept { release(p); }
void operator delete[](void *p, size_t) noexcept { release(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { release(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { release(p); }
