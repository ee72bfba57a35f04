// SPDX-License-Identifier: Apache-2.0
// Preloaded into linux.uml by run-in-vcan.sh: lets Debian 12's User-Mode-Linux run on hosts whose
// XSAVE area is larger than the buffer UML keeps for a guest thread's FPU state.
//
// UML (kernel 6.1) saves a guest thread's FPU state with PTRACE_GETREGSET(NT_X86_XSTATE) into a
// fixed buffer and restores it with PTRACE_SETREGSET from that buffer. The host kernel hands out a
// truncated state on GET, but takes a SET only with the whole XSAVE area; a shorter one fails with
// EFAULT. On a CPU with AVX-512 and AMX the area is several KiB, longer than UML's buffer, so the
// guest's first process dies ("userspace - ptrace set fp regs failed, errno = 14", then "Attempted
// to kill init"). This shim completes each short request to the host's full size:
//   GET: reads the whole area, gives UML its prefix, and keeps the whole image, keyed by UML's
//        buffer (one per guest thread);
//   SET: takes the kept image of that buffer (or, for a buffer not seen yet, the traced process's
//        present state), lays UML's prefix over it and writes the whole area.
// A guest thread therefore keeps its complete vector state (AVX-512 registers included) across
// preemption, as on the host. Requests already long enough and all other ptrace calls pass
// through unchanged, so the shim changes nothing on hosts UML already fits.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <elf.h>
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ptrace.h>
#include <sys/syscall.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

enum { kProbeBytes = 64 * 1024, kSlots = 8192 };

struct slot {
    const void* key;      // UML's buffer for one guest thread
    unsigned char* image; // the whole XSAVE area last read or written for it
};

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static size_t full_size;          // the host's XSAVE area for ptrace, learnt on first use
static unsigned char* scratch;    // full_size bytes
static struct slot slots[kSlots]; // open addressing, linear probing; keys are never removed
static int reported;

static long raw_regset(long request, pid_t pid, void* buf, size_t len, size_t* got) {
    struct iovec iov = {buf, len};
    long rc = syscall(SYS_ptrace, request, (long)pid, (long)NT_X86_XSTATE, &iov);
    if (got)
        *got = iov.iov_len;
    return rc;
}

// Learns the host's size from a GET with a buffer longer than any XSAVE area (the kernel shortens
// iov_len to what it wrote). Returns 0 or -1 with errno set.
static int learn_size(pid_t pid) {
    if (full_size)
        return 0;
    unsigned char* probe = malloc(kProbeBytes);
    if (!probe)
        return errno = ENOMEM, -1;
    size_t got = 0;
    if (raw_regset(PTRACE_GETREGSET, pid, probe, kProbeBytes, &got) < 0) {
        int e = errno;
        free(probe);
        return errno = e, -1;
    }
    free(probe);
    scratch = malloc(got);
    if (!scratch)
        return errno = ENOMEM, -1;
    full_size = got;
    return 0;
}

static struct slot* find_slot(const void* key, int create) {
    size_t i = ((uintptr_t)key >> 4) % kSlots;
    for (size_t n = 0; n < kSlots; ++n, i = (i + 1) % kSlots) {
        if (slots[i].key == key)
            return &slots[i];
        if (!slots[i].key) {
            if (!create)
                return NULL;
            unsigned char* image = malloc(full_size);
            if (!image)
                return NULL;
            slots[i].key = key;
            slots[i].image = image;
            return &slots[i];
        }
    }
    return NULL; // table full: SET falls back to the traced process's present state
}

static void report(size_t uml_len) {
    if (reported)
        return;
    reported = 1;
    // To UML's console log (run-in-vcan.sh --keep keeps it), once: the sizes behind the shim.
    fprintf(stderr, "uml-xstate-shim: UML asks for %zu bytes of XSAVE state, the host has %zu\n",
            uml_len, full_size);
}

static long xstate_get(pid_t pid, struct iovec* iov) {
    if (learn_size(pid) < 0)
        return -1;
    if (iov->iov_len >= full_size)
        return raw_regset(PTRACE_GETREGSET, pid, iov->iov_base, iov->iov_len, &iov->iov_len);
    report(iov->iov_len);
    if (raw_regset(PTRACE_GETREGSET, pid, scratch, full_size, NULL) < 0)
        return -1;
    memcpy(iov->iov_base, scratch, iov->iov_len);
    struct slot* s = find_slot(iov->iov_base, 1);
    if (s)
        memcpy(s->image, scratch, full_size);
    return 0;
}

static long xstate_set(pid_t pid, struct iovec* iov) {
    if (learn_size(pid) < 0)
        return -1;
    if (iov->iov_len >= full_size)
        return raw_regset(PTRACE_SETREGSET, pid, iov->iov_base, iov->iov_len, &iov->iov_len);
    report(iov->iov_len);
    struct slot* s = find_slot(iov->iov_base, 0);
    if (s)
        memcpy(scratch, s->image, full_size);
    else if (raw_regset(PTRACE_GETREGSET, pid, scratch, full_size, NULL) < 0)
        return -1;
    memcpy(scratch, iov->iov_base, iov->iov_len);
    if (raw_regset(PTRACE_SETREGSET, pid, scratch, full_size, NULL) < 0)
        return -1;
    if (s)
        memcpy(s->image, scratch, full_size);
    return 0;
}

long ptrace(enum __ptrace_request request, ...) {
    va_list ap;
    va_start(ap, request);
    pid_t pid = va_arg(ap, pid_t);
    void* addr = va_arg(ap, void*);
    void* data = va_arg(ap, void*);
    va_end(ap);

    if ((request == PTRACE_GETREGSET || request == PTRACE_SETREGSET) &&
        (uintptr_t)addr == NT_X86_XSTATE && data != NULL) {
        pthread_mutex_lock(&lock);
        long rc = request == PTRACE_GETREGSET ? xstate_get(pid, data) : xstate_set(pid, data);
        int e = errno;
        pthread_mutex_unlock(&lock);
        errno = e;
        return rc;
    }

    static long (*real)(enum __ptrace_request, ...);
    if (!real)
        *(void**)&real = dlsym(RTLD_NEXT, "ptrace");
    if (!real)
        return errno = ENOSYS, -1;
    return real(request, pid, addr, data);
}
