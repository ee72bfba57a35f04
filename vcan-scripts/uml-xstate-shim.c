// SPDX-License-Identifier: Apache-2.0
// Preloaded into linux.uml by run-in-vcan.sh: lets Debian 12's User-Mode-Linux run on hosts whose
// XSAVE area is larger than the buffer UML keeps for a guest thread's FPU state.
//
// UML (kernel 6.1) saves a guest thread's FPU state with PTRACE_GETREGSET(NT_X86_XSTATE) into a
// fixed 2696-byte buffer (the XSAVE layout up to and including PKRU: x87, SSE, AVX, AVX-512) and
// restores it with PTRACE_SETREGSET from that buffer. The host kernel hands out a truncated state
// on GET, but takes a SET only with the whole XSAVE area; a shorter one fails with EFAULT. On a
// CPU with AMX the area is 11008 bytes (tile configuration and tile data follow PKRU), so the
// guest's first process dies ("userspace - ptrace set fp regs failed, errno = 14", then
// "Attempted to kill init"). This shim completes each short SET: it reads the traced process's
// whole present area, lays UML's bytes over its start and writes the whole area back. Everything
// a guest thread can use lies in UML's part: a guest cannot enable AMX (that takes
// arch_prctl(ARCH_REQ_XCOMP_PERM), which UML 6.1 does not offer), so the AMX part stays in its
// initial state, as the header in UML's part says. GETs, requests already long enough and all
// other ptrace calls pass through unchanged: on hosts UML already fits the shim changes nothing.
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

enum { kProbeBytes = 64 * 1024 };

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static size_t full_size;       // the host's XSAVE area for ptrace, learnt on first use
static unsigned char* scratch; // full_size bytes
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

static long xstate_set(pid_t pid, struct iovec* iov) {
    if (learn_size(pid) < 0)
        return -1;
    if (iov->iov_len >= full_size)
        return raw_regset(PTRACE_SETREGSET, pid, iov->iov_base, iov->iov_len, &iov->iov_len);
    if (!reported) {
        reported = 1; // once, to UML's console log (run-in-vcan.sh --keep keeps it)
        fprintf(stderr,
                "uml-xstate-shim: UML asks for %zu bytes of XSAVE state, the host has %zu\n",
                iov->iov_len, full_size);
    }
    if (raw_regset(PTRACE_GETREGSET, pid, scratch, full_size, NULL) < 0)
        return -1;
    memcpy(scratch, iov->iov_base, iov->iov_len);
    return raw_regset(PTRACE_SETREGSET, pid, scratch, full_size, NULL);
}

long ptrace(enum __ptrace_request request, ...) {
    va_list ap;
    va_start(ap, request);
    pid_t pid = va_arg(ap, pid_t);
    void* addr = va_arg(ap, void*);
    void* data = va_arg(ap, void*);
    va_end(ap);

    if (request == PTRACE_SETREGSET && (uintptr_t)addr == NT_X86_XSTATE && data != NULL) {
        pthread_mutex_lock(&lock);
        long rc = xstate_set(pid, data);
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
