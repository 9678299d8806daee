/*
 * A stand-in for Windows' bcryptprimitives.dll, for running the tests under Wine 8.0 only
 * (Wine 8.0 lacks the DLL; Windows 10 and 11 have it). Rust's standard library takes its
 * random bytes (HashMap keys) from ProcessPrng; this one asks BCryptGenRandom. Never shipped
 * in an archive: it lies next to the test program, where Windows looks for DLLs first.
 */
#include <windows.h>
#include <bcrypt.h>

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG chunk = length > 0x40000000 ? 0x40000000 : (ULONG)length;
        if (BCryptGenRandom(NULL, data, chunk, BCRYPT_USE_SYSTEM_PREFERRED_RNG) != 0) return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
