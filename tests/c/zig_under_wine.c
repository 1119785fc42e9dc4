/*
 * zig.exe for the tests under Wine 8 only (tests/test_windows_wine.py): not
 * part of pdbfs. Windows' zig does not run under Wine as it is, for three
 * gaps of Wine's ntdll, each answered here in the zig process it starts:
 *
 *  - NtLockFile and NtUnlockFile refuse any call with an I/O status block
 *    (STATUS_NOT_IMPLEMENTED), and zig locks every cache file so: the calls
 *    go on without it, and Wine's "lock held" (STATUS_FILE_LOCK_CONFLICT) is
 *    answered as Windows answers (STATUS_LOCK_NOT_GRANTED), which zig waits on;
 *  - NtSetInformationFile has no FileDispositionInformationEx (64) nor
 *    FileRenameInformationEx (65): they are passed as the classes 13 and 10;
 *  - NtQueryAttributesFile looks a name relative to a folder handle up from
 *    the current folder instead: zig runs in its library folder, whose files
 *    it looks up so (pdbfs gives it absolute paths only).
 *
 * Each function's syscall thunk (mov r10, rcx; mov eax, N; ...) gets a jump
 * to a stub that fixes the arguments and goes on into the thunk.
 *
 *   zig.exe ARGS...      runs %REAL_ZIG% ARGS... and returns its exit status
 */
#include <windows.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <wchar.h>

/* Each stub: ``pre`` (fixing the arguments), the thunk's first 8 bytes
 * (mov r10, rcx; mov eax, N), a jump back to the rest of the thunk. */
static int patch(HANDLE proc, const char *name, const unsigned char *pre, size_t npre) {
    unsigned char *f = (unsigned char *)GetProcAddress(GetModuleHandleA("ntdll.dll"), name);
    unsigned char stub[128], jmp[8];
    unsigned char *mem = NULL;
    uintptr_t a;
    DWORD old;
    SIZE_T n;
    int32_t rel;
    if (!f || f[0] != 0x4c || f[1] != 0x8b || f[2] != 0xd1 || f[3] != 0xb8) return 0;
    for (a = ((uintptr_t)f & ~(uintptr_t)0xFFFF) - 0x10000; a > (uintptr_t)f - 0x70000000u; a -= 0x10000) {
        mem = VirtualAllocEx(proc, (void *)a, 4096, MEM_COMMIT | MEM_RESERVE, PAGE_EXECUTE_READWRITE);
        if (mem) break;
    }
    if (!mem) return 0;
    memcpy(stub, pre, npre);
    memcpy(stub + npre, f, 8);
    stub[npre + 8] = 0xe9;
    rel = (int32_t)((intptr_t)(f + 8) - (intptr_t)(mem + npre + 13));
    memcpy(stub + npre + 9, &rel, 4);
    if (!WriteProcessMemory(proc, mem, stub, npre + 13, &n)) return 0;
    jmp[0] = 0xe9;
    rel = (int32_t)((intptr_t)mem - (intptr_t)(f + 5));
    memcpy(jmp + 1, &rel, 4);
    jmp[5] = jmp[6] = jmp[7] = 0x90;
    if (!VirtualProtectEx(proc, f, 8, PAGE_EXECUTE_READWRITE, &old)) return 0;
    if (!WriteProcessMemory(proc, f, jmp, 8, &n)) return 0;
    VirtualProtectEx(proc, f, 8, old, &old);
    FlushInstructionCache(proc, f, 8);
    return 1;
}

/* NtLockFile: called again from a frame of its own with the I/O status block
 * (5th argument) and the key (8th) dropped; Wine's "lock held"
 * (STATUS_FILE_LOCK_CONFLICT) answered as Windows does (STATUS_LOCK_NOT_GRANTED):
 *   sub rsp,0x58; [rsp+0x20..0x48] = NULL, arg6, arg7, NULL, arg9, arg10;
 *   call the thunk (right after this); cmp eax,0xC0000054; jne 1f;
 *   mov eax,0xC0000055; 1: add rsp,0x58; ret */
static const unsigned char LOCK[] = {
    0x48, 0x83, 0xec, 0x58, 0x48, 0xc7, 0x44, 0x24, 0x20, 0x00, 0x00, 0x00, 0x00, 0x48, 0x8b,
    0x84, 0x24, 0x88, 0x00, 0x00, 0x00, 0x48, 0x89, 0x44, 0x24, 0x28, 0x48, 0x8b, 0x84, 0x24,
    0x90, 0x00, 0x00, 0x00, 0x48, 0x89, 0x44, 0x24, 0x30, 0x48, 0xc7, 0x44, 0x24, 0x38, 0x00,
    0x00, 0x00, 0x00, 0x48, 0x8b, 0x84, 0x24, 0xa0, 0x00, 0x00, 0x00, 0x48, 0x89, 0x44, 0x24,
    0x40, 0x48, 0x8b, 0x84, 0x24, 0xa8, 0x00, 0x00, 0x00, 0x48, 0x89, 0x44, 0x24, 0x48, 0xe8,
    0x11, 0x00, 0x00, 0x00, 0x3d, 0x54, 0x00, 0x00, 0xc0, 0x75, 0x05, 0xb8, 0x55, 0x00, 0x00,
    0xc0, 0x48, 0x83, 0xc4, 0x58, 0xc3
};
/* NtUnlockFile: the I/O status block (2nd argument) and the key (5th) dropped */
static const unsigned char UNLOCK[] = {0x31, 0xd2, 0x48, 0xc7, 0x44, 0x24, 0x28, 0, 0, 0, 0};
/* NtSetInformationFile: class 64 (FileDispositionInformationEx) as 13, class 65
 * (FileRenameInformationEx) as 10, their flags reduced to delete / replace */
static const unsigned char SETINFO[] = {
    0x83, 0x7c, 0x24, 0x28, 0x40,               /* cmp dword [rsp+0x28], 64 */
    0x75, 0x0e,                                 /* jne L1 */
    0xc7, 0x44, 0x24, 0x28, 0x0d, 0, 0, 0,      /* mov dword [rsp+0x28], 13 */
    0x41, 0x83, 0x20, 0x01,                     /* and dword [r8], 1 */
    0xeb, 0x13,                                 /* jmp L2 */
    0x83, 0x7c, 0x24, 0x28, 0x41,               /* L1: cmp dword [rsp+0x28], 65 */
    0x75, 0x0c,                                 /* jne L2 */
    0xc7, 0x44, 0x24, 0x28, 0x0a, 0, 0, 0,      /* mov dword [rsp+0x28], 10 */
    0x41, 0x83, 0x20, 0x01,                     /* and dword [r8], 1 */
};                                              /* L2: */

int main(void) {
    wchar_t *cmd = GetCommandLineW(), *rest, real[MAX_PATH], libdir[MAX_PATH + 16], *line, *slash;
    STARTUPINFOW si;
    PROCESS_INFORMATION pi;
    DWORD code = 1;
    size_t len;
    int quoted = 0;
    if (!GetEnvironmentVariableW(L"REAL_ZIG", real, MAX_PATH)) {
        fprintf(stderr, "zig_under_wine: set REAL_ZIG\n");
        return 1;
    }
    for (rest = cmd; *rest && (quoted || (*rest != L' ' && *rest != L'\t')); rest++)
        if (*rest == L'"') quoted = !quoted;
    len = wcslen(real) + wcslen(rest) + 4;
    line = (wchar_t *)malloc(len * sizeof(wchar_t));
    swprintf(line, len, L"\"%ls\"%ls", real, rest);
    memset(&si, 0, sizeof si);
    si.cb = sizeof si;
    /* Wine's NtQueryAttributesFile looks a name relative to a folder handle up
     * from the current folder instead: zig looks its library files up so
     * (the mingw .def files), so zig runs in its library folder (pdbfs gives
     * it absolute paths only) */
    wcscpy(libdir, real);
    slash = wcsrchr(libdir, L'\\');
    if (slash) wcscpy(slash, L"\\..\\Lib\\zig");
    if (!CreateProcessW(real, line, NULL, NULL, TRUE, CREATE_SUSPENDED, NULL, slash ? libdir : NULL, &si, &pi)) {
        fprintf(stderr, "zig_under_wine: cannot start %ls (%lu)\n", real, GetLastError());
        return 1;
    }
    if (!patch(pi.hProcess, "NtLockFile", LOCK, sizeof LOCK) || !patch(pi.hProcess, "NtUnlockFile", UNLOCK, sizeof UNLOCK)
        || !patch(pi.hProcess, "NtSetInformationFile", SETINFO, sizeof SETINFO)) {
        fprintf(stderr, "zig_under_wine: cannot patch ntdll\n");
        TerminateProcess(pi.hProcess, 1);
        return 1;
    }
    ResumeThread(pi.hThread);
    WaitForSingleObject(pi.hProcess, INFINITE);
    GetExitCodeProcess(pi.hProcess, &code);
    return (int)code;
}
