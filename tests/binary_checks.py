"""What a Windows DLL or a Mach-O library imports and exports, read with
struct from the file formats (PE/COFF; Mach-O, thin or universal), so the
tests need no binutils for foreign platforms."""
import struct

#: Mach-O CPU types
CPU_X86_64, CPU_ARM64 = 0x01000007, 0x0100000C
LC_SYMTAB, LC_LOAD_DYLIB, LC_LOAD_WEAK_DYLIB, LC_REEXPORT_DYLIB = 0x2, 0xC, 0x80000018, 0x8000001F
#: the library's own name; the oldest macOS (before 10.14's loader: VERSION_MIN_MACOSX)
LC_ID_DYLIB, LC_VERSION_MIN_MACOSX, LC_BUILD_VERSION = 0xD, 0x24, 0x32
PLATFORM_MACOS = 1


def pe(data: bytes) -> dict:
    """{'machine', 'imports' (DLL names), 'exports' (function names)} of a PE32+ file."""
    at = struct.unpack_from("<I", data, 0x3C)[0]
    assert data[at:at + 4] == b"PE\0\0", "not a PE file"
    machine, nsec, _, _, _, opt_size, _ = struct.unpack_from("<HHIIIHH", data, at + 4)
    opt = at + 24
    assert struct.unpack_from("<H", data, opt)[0] == 0x20B, "not PE32+"
    exp_rva, _, imp_rva, _ = struct.unpack_from("<IIII", data, opt + 112)
    sections = [struct.unpack_from("<8xIIII", data, opt + opt_size + 40 * i) for i in range(nsec)]

    def off(rva):
        for vsize, vaddr, rsize, rptr in sections:
            if vaddr <= rva < vaddr + max(vsize, rsize):
                return rva - vaddr + rptr
        raise ValueError(f"RVA {rva:#x} in no section")

    def cstr(rva):
        o = off(rva)
        return data[o:data.index(b"\0", o)].decode()
    imports, o = [], off(imp_rva) if imp_rva else None
    while o is not None:
        name_rva = struct.unpack_from("<IIIII", data, o)[3]
        if name_rva == 0:
            break
        imports.append(cstr(name_rva))
        o += 20
    exports = []
    if exp_rva:
        n, _, names = struct.unpack_from("<III", data, off(exp_rva) + 24)
        exports = [cstr(struct.unpack_from("<I", data, off(names) + 4 * i)[0]) for i in range(n)]
    return {"machine": machine, "imports": imports, "exports": exports}


def macho_slices(data: bytes) -> list[bytes]:
    """The thin 64-bit Mach-O images of a file, universal or not."""
    if struct.unpack_from(">I", data)[0] == 0xCAFEBABE:
        n = struct.unpack_from(">I", data, 4)[0]
        out = []
        for i in range(n):
            _, _, offset, size, _ = struct.unpack_from(">IIIII", data, 8 + 20 * i)
            out.append(data[offset:offset + size])
        return out
    return [data]


def _version(v: int) -> tuple[int, int, int]:
    """A Mach-O version word (xxxx.yy.zz in nibbles) as (major, minor, patch)."""
    return v >> 16, (v >> 8) & 0xFF, v & 0xFF


def macho(thin: bytes) -> dict:
    """{'cpu', 'filetype', 'imports' (dylib paths), 'exports' (external
    defined symbols, without the leading underscore), 'ids' (LC_ID_DYLIB
    names), 'min_macos' (every (major, minor, patch) declared for macOS by
    LC_BUILD_VERSION or LC_VERSION_MIN_MACOSX), 'build_platforms' (the
    platform of every LC_BUILD_VERSION)} of a thin Mach-O."""
    magic, cpu, _, filetype, ncmds, _, _, _ = struct.unpack_from("<8I", thin)
    assert magic == 0xFEEDFACF, "not a 64-bit little-endian Mach-O"
    imports, exports, ids, min_macos, platforms, o = [], [], [], [], [], 32
    for _ in range(ncmds):
        cmd, size = struct.unpack_from("<II", thin, o)
        if cmd in (LC_LOAD_DYLIB, LC_LOAD_WEAK_DYLIB, LC_REEXPORT_DYLIB, LC_ID_DYLIB):
            name = o + struct.unpack_from("<I", thin, o + 8)[0]
            (ids if cmd == LC_ID_DYLIB else imports).append(thin[name:thin.index(b"\0", name)].decode())
        elif cmd == LC_VERSION_MIN_MACOSX:
            min_macos.append(_version(struct.unpack_from("<I", thin, o + 8)[0]))
        elif cmd == LC_BUILD_VERSION:
            platform, minos = struct.unpack_from("<II", thin, o + 8)
            platforms.append(platform)
            min_macos += [_version(minos)] if platform == PLATFORM_MACOS else []
        elif cmd == LC_SYMTAB:
            symoff, nsyms, stroff, _ = struct.unpack_from("<IIII", thin, o + 8)
            for i in range(nsyms):
                strx, ntype, _, _, _ = struct.unpack_from("<IBBHQ", thin, symoff + 16 * i)
                if ntype & 0x01 and ntype & 0x0E == 0x0E and not ntype & 0x10:   # N_EXT, N_SECT, not N_PEXT
                    s = stroff + strx
                    exports.append(thin[s:thin.index(b"\0", s)].decode().removeprefix("_"))
        o += size
    return {"cpu": cpu, "filetype": filetype, "imports": imports, "exports": exports, "ids": ids,
            "min_macos": min_macos, "build_platforms": platforms}
