#!/usr/bin/env python3
"""Helpers for libpbf's C# packages (the Unity package and the NuGet package), standard library only.

  pbf_packages.py header-version                 the version in include/pbf_c_api.h (e.g. 2.0.0)
  pbf_packages.py header-functions               the pbf_* functions the header declares
  pbf_packages.py exports FILE                   the functions a libpbf.so (ELF) or pbf.dll (PE) exports
  pbf_packages.py deps FILE                      the libraries it needs (DT_NEEDED / PE imports)
  pbf_packages.py check-native FILE KIND [GPU]   KIND linux-x64 | win-x64: format, CPU, exports == header,
                                                 no CUDA library linked, the kernels' fatbin embedded
                                                 (GPU: required (default) | absent: a CPU-only build)
  pbf_packages.py native-selftest SO DLL         break copies of a libpbf.so and pbf.dll built with CUDA:
                                                 the native checks must fail on each
  pbf_packages.py unity-metas DIR [--write]      list (or write) the .meta files DIR lacks
  pbf_packages.py unity-check DIR                validate a Unity package the way Unity's importer reads it
  pbf_packages.py unity-selftest DIR             break copies of DIR one way at a time: each must fail
  pbf_packages.py unity-provenance DIR           rewrite the plugins' provenance table (update script)
  pbf_packages.py nupkg NUSPEC BASEDIR OUT [--optional TARGET]...
                                                 assemble a .nupkg from a .nuspec and its <files>
  pbf_packages.py nupkg-check NUPKG              validate a .nupkg's layout and nuspec

Exit status 0 when everything checked holds, 1 otherwise.
"""
import hashlib
import json
import os
import re
import struct
import subprocess
import sys
import uuid
import xml.etree.ElementTree as ET
import zipfile

baseline = set()
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HEADER = os.path.join(ROOT, "include", "pbf_c_api.h")


# ---------------------------------------------------------------------------------------------
# The header


def _header_text():
    with open(HEADER, encoding="utf-8") as f:
        text = f.read()
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", " ", text)


def header_version():
    text = _header_text()
    parts = []
    for name in ("MAJOR", "MINOR", "PATCH"):
        m = re.search(r"#\s*define\s+PBF_VERSION_%s\s+(\d+)" % name, text)
        if not m:
            raise SystemExit("pbf_packages.py: PBF_VERSION_%s not found in %s" % (name, HEADER))
        parts.append(m.group(1))
    return ".".join(parts)


def header_functions():
    """The exported functions: every declaration that starts with PBF_API (static inline helpers
    are not exported and do not start with it)."""
    text = _header_text()
    names = set()
    for m in re.finditer(r"\bPBF_API\b([^;{]*?)\b(pbf_\w+)\s*\(", text):
        if "define" in m.group(1):
            continue
        names.add(m.group(2))
    return names


# ---------------------------------------------------------------------------------------------
# ELF and PE: exported functions, needed libraries, CPU


class NativeInfo(object):
    def __init__(self, fmt, machine, exports, needed, sections=(), data=b""):
        self.format = fmt          # "ELF64" | "PE32+" | ...
        self.machine = machine     # "x86_64" | ...
        self.exports = exports     # set of exported function names
        self.needed = needed       # list of libraries it links against
        self.sections = list(sections)  # (name, file offset, size) of each section with file data
        self.fatbin = find_fatbin(data, self.sections)
        self.size = len(data)


def _elf_info(data):
    if data[4] != 2 or data[5] != 1:
        return NativeInfo("ELF (not 64-bit little-endian)", "?", set(), [])
    e_machine = struct.unpack_from("<H", data, 18)[0]
    e_shoff = struct.unpack_from("<Q", data, 40)[0]
    e_shentsize, e_shnum, e_shstrndx = struct.unpack_from("<HHH", data, 58)
    sections, named = [], []
    for i in range(e_shnum):
        off = e_shoff + i * e_shentsize
        (name, stype, flags, addr, offset, size, link, info, align, entsize) = struct.unpack_from(
            "<IIQQQQIIQQ", data, off)
        sections.append((stype, offset, size, link, entsize))
        named.append((name, stype, offset, size))
    names_off = sections[e_shstrndx][1] if e_shstrndx < len(sections) else 0
    with_data = [(data[names_off + n:data.index(b"\0", names_off + n)].decode(errors="replace"), o, sz)
                 for n, t, o, sz in named if t not in (0, 8)]  # SHT_NULL, SHT_NOBITS: no file data
    exports, needed = set(), []
    for stype, offset, size, link, entsize in sections:
        if stype == 11:  # SHT_DYNSYM
            str_off = sections[link][1]
            for i in range(1, size // 24):
                st_name, st_info, st_other, st_shndx, st_value, st_size = struct.unpack_from(
                    "<IBBHQQ", data, offset + i * 24)
                bind, typ, vis = st_info >> 4, st_info & 0xF, st_other & 0x3
                if st_shndx != 0 and bind in (1, 2) and typ == 2 and vis in (0, 1):
                    end = data.index(b"\0", str_off + st_name)
                    exports.add(data[str_off + st_name:end].decode())
        if stype == 6:  # SHT_DYNAMIC
            str_off = sections[link][1]
            for i in range(size // 16):
                tag, val = struct.unpack_from("<qQ", data, offset + i * 16)
                if tag == 0:
                    break
                if tag == 1:  # DT_NEEDED
                    end = data.index(b"\0", str_off + val)
                    needed.append(data[str_off + val:end].decode())
    machine = {62: "x86_64", 183: "arm64", 3: "x86"}.get(e_machine, "machine %d" % e_machine)
    return NativeInfo("ELF64", machine, exports, needed, with_data, data)


def _pe_info(data):
    pe = struct.unpack_from("<I", data, 0x3C)[0]
    if data[pe:pe + 4] != b"PE\0\0":
        return NativeInfo("MZ (not PE)", "?", set(), [])
    machine_id, nsections = struct.unpack_from("<HH", data, pe + 4)
    opt_size = struct.unpack_from("<H", data, pe + 20)[0]
    opt = pe + 24
    magic = struct.unpack_from("<H", data, opt)[0]
    fmt = {0x20B: "PE32+", 0x10B: "PE32"}.get(magic, "PE?")
    dirs = opt + (112 if magic == 0x20B else 96)
    sections, named = [], []
    sec = opt + opt_size
    for i in range(nsections):
        vsize, vaddr, rawsize, rawptr = struct.unpack_from("<IIII", data, sec + i * 40 + 8)
        sections.append((vaddr, max(vsize, rawsize), rawptr))
        named.append((data[sec + i * 40:sec + i * 40 + 8].rstrip(b"\0").decode(errors="replace"), rawptr, rawsize))

    def off(rva):
        for vaddr, size, rawptr in sections:
            if vaddr <= rva < vaddr + size:
                return rva - vaddr + rawptr
        raise ValueError("RVA 0x%x outside every section" % rva)

    def cstr(o):
        return data[o:data.index(b"\0", o)].decode()

    exports, needed = set(), []
    exp_rva, exp_size = struct.unpack_from("<II", data, dirs)
    if exp_rva:
        e = off(exp_rva)
        nnames, _, names_rva = struct.unpack_from("<III", data, e + 24)
        for i in range(nnames):
            exports.add(cstr(off(struct.unpack_from("<I", data, off(names_rva) + 4 * i)[0])))
    imp_rva = struct.unpack_from("<I", data, dirs + 8)[0]
    if imp_rva:
        d = off(imp_rva)
        while True:
            fields = struct.unpack_from("<IIIII", data, d)
            if not any(fields):
                break
            needed.append(cstr(off(fields[3])))
            d += 20
    machine = {0x8664: "x86_64", 0x14C: "x86", 0xAA64: "arm64"}.get(machine_id, "machine 0x%x" % machine_id)
    return NativeInfo(fmt, machine, exports, needed, named, data)


def native_info(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"\x7fELF":
        return _elf_info(data)
    if data[:2] == b"MZ":
        return _pe_info(data)
    return NativeInfo("unknown", "?", set(), [])


# libpbf's CUDA kernels: one fatbin (nvcc -fatbin) placed in the library's read-only data
# (cmake/pbf_fatbin.c.in), which the library hands to the driver at run time. A fatbin starts
# with this magic (little-endian), a version, its header's size and the size of its entries.
FATBIN_MAGIC = struct.pack("<I", 0xBA55ED50)
READONLY_SECTIONS = (".rodata", ".rdata")


def find_fatbin(data, sections):
    """libpbf's embedded fatbin: {"section", "offset", "bytes", "archs"} or None. Looked for in the
    read-only data section, where libpbf places it; a fatbin elsewhere (.nv_fatbin, where nvcc's
    CUDA runtime registration puts kernels) is not libpbf's."""
    for name, start, size in sections:
        if name not in READONLY_SECTIONS:
            continue
        at = data.find(FATBIN_MAGIC, start, start + size)
        while at >= 0:
            version, header, body = struct.unpack_from("<HHQ", data, at + 4)
            end = at + header + body
            if version == 1 and header == 16 and body > 0 and end <= start + size:
                archs, e = [], at + header
                while e + 32 <= end:  # entries: kind (1 PTX, 2 ELF), header size, payload size, arch
                    kind, _, ehead, payload = struct.unpack_from("<HHIQ", data, e)
                    arch = struct.unpack_from("<I", data, e + 28)[0]
                    if ehead < 32 or e + ehead + payload > end:
                        break
                    archs.append(("sm_%d" if kind == 2 else "compute_%d") % arch)
                    e += ehead + payload
                if archs:
                    return {"section": name, "offset": at, "bytes": end - at, "archs": archs,
                            "sha256": hashlib.sha256(data[at:end]).hexdigest()}
            at = data.find(FATBIN_MAGIC, at + 4, start + size)
    return None


# What a library must not link against: libpbf opens the NVIDIA driver itself at run time.
CUDA_LIBRARY = re.compile(r"^(libcudart|libcuda\.|nvcuda|cudart)", re.I)
# Each binary with all its GPU code (every architecture) stays within this size.
MAX_NATIVE_BYTES = 25 * 1000 * 1000

# Libraries every Windows x64 machine has; anything else must ship beside pbf.dll.
WINDOWS_SYSTEM_DLLS = {"kernel32.dll", "msvcrt.dll", "user32.dll", "advapi32.dll", "ws2_32.dll",
                       "bcrypt.dll", "ntdll.dll", "shell32.dll", "ole32.dll", "ucrtbase.dll",
                       "vcruntime140.dll", "msvcp140.dll", "gdi32.dll", "opengl32.dll"}


def check_native(path, kind, report, gpu="required"):
    """Format, CPU and exports of a native libpbf against the header, and that it carries the GPU:
    libpbf's kernels embedded, no CUDA library linked. kind: linux-x64 | win-x64. gpu: "required",
    "absent" (a CPU-only build: no kernels either), or why the kernels are not required here (their
    absence is then a warning)."""
    name = os.path.relpath(path, ROOT) if path.startswith(ROOT) else path
    if not os.path.isfile(path):
        report.fail("%s: missing" % name)
        return None
    info = native_info(path)
    want_fmt = {"linux-x64": "ELF64", "win-x64": "PE32+"}[kind]
    if info.format != want_fmt or info.machine != "x86_64":
        report.fail("%s: %s %s, expected %s x86_64 for %s" % (name, info.format, info.machine, want_fmt, kind))
        return info
    report.ok("%s: %s x86_64" % (name, info.format))
    want = header_functions()
    missing, extra = sorted(want - info.exports), sorted(info.exports - want)
    if missing or extra:
        report.fail("%s: exports differ from include/pbf_c_api.h: missing %s, extra %s"
                    % (name, missing[:8] or "none", extra[:8] or "none"))
    else:
        report.ok("%s: exports exactly the header's %d pbf_* functions" % (name, len(want)))
    if kind == "win-x64":
        foreign = [d for d in info.needed if d.lower() not in WINDOWS_SYSTEM_DLLS
                   and not d.lower().startswith("api-ms-win-") and not CUDA_LIBRARY.match(d)]
        if foreign:
            report.fail("%s: needs %s, which a Windows machine does not have (link them statically)"
                        % (name, ", ".join(foreign)))
        else:
            report.ok("%s: needs only system DLLs (%s)" % (name, ", ".join(info.needed)))
    else:
        report.note("%s: needs %s" % (name, ", ".join(info.needed)))
    cuda = [d for d in info.needed if CUDA_LIBRARY.match(d)]
    if cuda:
        report.fail("%s: links %s: libpbf must open the NVIDIA driver at run time, not link it" % (name, ", ".join(cuda)))
    else:
        report.ok("%s: links no CUDA library" % name)
    f = info.fatbin
    runtime = [s for s, _, _ in info.sections if s == ".nv_fatbin"]
    if gpu == "absent":
        (report.fail if f else report.ok)("%s: %s (a CPU-only build)" % (name, "carries a fatbin" if f else "no CUDA kernels"))
    elif f and not runtime:
        report.ok("%s: carries libpbf's CUDA kernels: a fatbin of %.1f MB in %s (%s)"
                  % (name, f["bytes"] / 1e6, f["section"], ", ".join(f["archs"])))
    else:
        why = ("its kernels are in .nv_fatbin, a CUDA runtime build's" if runtime
               else "no fatbin in %s: a build without CUDA" % "/".join(READONLY_SECTIONS))
        if gpu == "required":
            report.fail("%s: does not carry libpbf's CUDA kernels (%s)" % (name, why))
        else:
            report.warn("%s: does not carry libpbf's CUDA kernels (%s); not required: %s" % (name, why, gpu))
    if info.size > MAX_NATIVE_BYTES:
        report.fail("%s: %.1f MB, over the %.0f MB a binary with all its GPU code may take"
                    % (name, info.size / 1e6, MAX_NATIVE_BYTES / 1e6))
    else:
        report.note("%s: %.1f MB" % (name, info.size / 1e6))
    return info


def check_same_kernels(infos, report):
    """The Linux and the Windows library carry the same kernels: one nvcc build serves both."""
    blobs = {name: info.fatbin for name, info in infos if info is not None and info.fatbin}
    if len(blobs) < 2:
        return
    if len({f["sha256"] for f in blobs.values()}) == 1:
        report.ok("%s carry the same kernels (fatbin sha256 %s)" % (" and ".join(blobs), next(iter(blobs.values()))["sha256"][:16]))
    else:
        report.fail("the kernels differ: %s" % "; ".join("%s %s (%s)" % (n, f["sha256"][:16], ", ".join(f["archs"]))
                                                       for n, f in blobs.items()))


def loaded_version(path):
    """pbf_get_version() of a libpbf.so, loaded here (None where it cannot be loaded)."""
    import ctypes
    try:
        lib = ctypes.CDLL(os.path.abspath(path))
    except OSError as e:
        return "not loadable: %s" % e
    lib.pbf_get_version.restype = ctypes.c_uint32
    v = lib.pbf_get_version()
    return "%d.%d.%d" % (v >> 22, (v >> 12) & 0x3FF, v & 0xFFF)


# ---------------------------------------------------------------------------------------------
# Reports


class Report(object):
    def __init__(self, title):
        self.title, self.passed, self.failed = title, 0, 0

    def ok(self, msg):
        self.passed += 1
        print("  ok    %s" % msg)

    def fail(self, msg):
        self.failed += 1
        print("  FAIL  %s" % msg)

    def warn(self, msg):
        print("  WARNING  %s" % msg)

    def note(self, msg):
        print("  note  %s" % msg)

    def close(self):
        print("%s: %d passed, %d failed" % (self.title, self.passed, self.failed))
        return 1 if self.failed else 0


# ---------------------------------------------------------------------------------------------
# Unity package


def unity_ignored(name):
    """Names Unity's asset database skips: hidden, ending in '~', 'cvs', '*.tmp'."""
    return (name.startswith(".") or name.endswith("~") or name.lower() == "cvs"
            or name.lower().endswith(".tmp"))


def unity_assets(root):
    """Every file and folder under root that Unity imports (root itself excluded), as paths
    relative to root, plus the .meta files found."""
    assets, metas = [], []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if not unity_ignored(d))
        for d in dirnames:
            assets.append((os.path.relpath(os.path.join(dirpath, d), root), True))
        for f in sorted(filenames):
            rel = os.path.relpath(os.path.join(dirpath, f), root)
            if f.endswith(".meta") and not f.startswith("."):
                metas.append(rel)
            elif not unity_ignored(f):
                assets.append((rel, False))
    return assets, metas


def asset_roots(package):
    """The package itself, and each sample folder (Samples~/X is copied into Assets/ on import,
    its .meta files with it, so it is validated like a package of its own)."""
    roots = [package]
    samples = os.path.join(package, "Samples~")
    if os.path.isdir(samples):
        roots += [os.path.join(samples, d) for d in sorted(os.listdir(samples))
                  if os.path.isdir(os.path.join(samples, d))]
    return roots


# Importer by file type. Native plugins carry their platform settings (PLUGIN_SETTINGS).
IMPORTERS = [
    (r"package\.json$", "PackageManifestImporter"),
    (r"\.cs$", "MonoImporter"),
    (r"\.asmdef$", "AssemblyDefinitionImporter"),
    (r"\.(so|dll|dylib|bundle)$", "PluginImporter"),
    (r"\.shader$", "ShaderImporter"),
    (r"\.(md|txt|json|xml)$", "TextScriptImporter"),
    (r"\.unity$", "DefaultImporter"),
    (r"\.mat$", "NativeFormatImporter"),
]

_TAIL = "  userData:\n  assetBundleName:\n  assetBundleVariant:\n"
META_BODIES = {
    "folder": "folderAsset: yes\nDefaultImporter:\n  externalObjects: {}\n" + _TAIL,
    "DefaultImporter": "DefaultImporter:\n  externalObjects: {}\n" + _TAIL,
    "PackageManifestImporter": "PackageManifestImporter:\n  externalObjects: {}\n" + _TAIL,
    "MonoImporter": ("MonoImporter:\n  externalObjects: {}\n  serializedVersion: 2\n"
                     "  defaultReferences: []\n  executionOrder: 0\n  icon: {instanceID: 0}\n" + _TAIL),
    "AssemblyDefinitionImporter": "AssemblyDefinitionImporter:\n  externalObjects: {}\n" + _TAIL,
    "ShaderImporter": ("ShaderImporter:\n  externalObjects: {}\n  defaultTextures: []\n"
                       "  nonModifiableTextures: []\n" + _TAIL),
    "TextScriptImporter": "TextScriptImporter:\n  externalObjects: {}\n" + _TAIL,
    "NativeFormatImporter": "NativeFormatImporter:\n  externalObjects: {}\n  mainObjectFileID: 2100000\n" + _TAIL,
}

# Desktop platforms in the serializedVersion 2 PluginImporter form (Unity 2021.3 reads and writes
# it; later versions read it). Per plugin: the editor OS and the one standalone target enabled.
DESKTOP = ["Linux64", "OSXUniversal", "Win", "Win64"]
PLUGIN_SETTINGS = {
    ".so": {"editor_os": "Linux", "standalone": "Linux64", "kind": "linux-x64"},
    ".dll": {"editor_os": "Windows", "standalone": "Win64", "kind": "win-x64"},
}


def plugin_meta_body(ext):
    s = PLUGIN_SETTINGS[ext]
    lines = ["PluginImporter:", "  externalObjects: {}", "  serializedVersion: 2", "  iconMap: {}",
             "  executionOrder: {}", "  defineConstraints: []", "  isPreloaded: 0",
             "  isOverridable: 0", "  isExplicitlyReferenced: 0", "  validateReferences: 1",
             "  platformData:",
             "  - first:", "      '': Any", "    second:", "      enabled: 0", "      settings:",
             "        Exclude Editor: 0"]
    for p in DESKTOP:
        lines.append("        Exclude %s: %d" % (p, 0 if p == s["standalone"] else 1))
    lines += ["  - first:", "      Any:", "    second:", "      enabled: 0", "      settings: {}",
              "  - first:", "      Editor: Editor", "    second:", "      enabled: 1", "      settings:",
              "        CPU: x86_64", "        DefaultValueInitialized: true",
              "        OS: %s" % s["editor_os"]]
    for p in DESKTOP:
        on = p == s["standalone"]
        lines += ["  - first:", "      Standalone: %s" % p, "    second:",
                  "      enabled: %d" % (1 if on else 0), "      settings:",
                  "        CPU: %s" % ("x86_64" if on else "None")]
    return "\n".join(lines) + "\n" + _TAIL


def importer_for(rel, is_dir):
    if is_dir:
        return "folder"
    for pattern, importer in IMPORTERS:
        if re.search(pattern, os.path.basename(rel)):
            return importer
    return "DefaultImporter"


def meta_guid(package_name, rel):
    """A fixed GUID from the package name and the asset's path: stable, and unique in practice."""
    return hashlib.md5(("%s/%s" % (package_name, rel.replace(os.sep, "/"))).encode()).hexdigest()


def meta_text(package_name, rel, is_dir):
    imp = importer_for(rel, is_dir)
    ext = os.path.splitext(rel)[1].lower()
    body = plugin_meta_body(ext) if imp == "PluginImporter" else META_BODIES[imp]
    return "fileFormatVersion: 2\nguid: %s\n%s" % (meta_guid(package_name, rel), body)


def package_name_of(package):
    try:
        with open(os.path.join(package, "package.json"), encoding="utf-8") as f:
            return json.load(f)["name"]
    except Exception:
        return "package"


def unity_metas(package, write):
    name = package_name_of(package)
    missing = 0
    for root in asset_roots(package):
        assets, _ = unity_assets(root)
        for rel, is_dir in assets:
            meta = os.path.join(root, rel) + ".meta"
            if os.path.exists(meta):
                continue
            missing += 1
            key = os.path.relpath(os.path.join(root, rel), package)
            print(("wrote " if write else "missing ") + os.path.relpath(meta, package))
            if write:
                with open(meta, "w", encoding="utf-8", newline="\n") as f:
                    f.write(meta_text(name, key, is_dir))
    if not write and missing:
        print("%d .meta files missing (write them with: %s unity-metas %s --write)"
              % (missing, sys.argv[0], package))
    return 1 if (missing and not write) else 0


def parse_plugin_platforms(text):
    """The platformData of a serializedVersion 2 PluginImporter meta:
    {(group, name): (enabled, {setting: value})}."""
    out, cur = {}, None
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.strip() == "- first:" and i + 1 < len(lines):
            key = lines[i + 1].strip()
            group, _, name = key.partition(":")
            cur = (group.strip().strip("'"), name.strip())
            out[cur] = [None, {}]
            i += 2
            continue
        if cur is not None:
            m = re.match(r"^      enabled: (\d)", line)
            if m:
                out[cur][0] = int(m.group(1))
            m = re.match(r"^        ([^:]+): (.*)$", line)
            if m:
                out[cur][1][m.group(1).strip()] = m.group(2).strip()
            if re.match(r"^  \w", line):
                cur = None
        i += 1
    return {k: (v[0], v[1]) for k, v in out.items()}


def check_plugin_meta(rel, text, report):
    ext = os.path.splitext(rel)[1].lower()
    if ext not in PLUGIN_SETTINGS:
        report.fail("%s: no platform settings are defined for a %s plugin" % (rel, ext))
        return
    s = PLUGIN_SETTINGS[ext]
    p = parse_plugin_platforms(text)
    problems = []
    any_entry = p.get(("", "Any")) or p.get(("Any", ""))
    if p.get(("Any", ""), (0,))[0] != 0:
        problems.append("enabled for Any platform")
    editor = p.get(("Editor", "Editor"))
    if not editor or editor[0] != 1 or editor[1].get("OS") != s["editor_os"] or editor[1].get("CPU") != "x86_64":
        problems.append("Editor must be enabled with OS %s, CPU x86_64 (got %s)" % (s["editor_os"], editor))
    for plat in DESKTOP:
        entry = p.get(("Standalone", plat))
        if plat == s["standalone"]:
            if not entry or entry[0] != 1 or entry[1].get("CPU") != "x86_64":
                problems.append("Standalone %s must be enabled with CPU x86_64 (got %s)" % (plat, entry))
        elif entry and entry[0] != 0:
            problems.append("Standalone %s must be disabled" % plat)
    if any_entry is not None:
        excl = any_entry[1]
        for plat in DESKTOP:
            want = "0" if plat == s["standalone"] else "1"
            if excl.get("Exclude " + plat) != want:
                problems.append("Any: 'Exclude %s' must be %s" % (plat, want))
        if excl.get("Exclude Editor") != "0":
            problems.append("Any: 'Exclude Editor' must be 0")
    if problems:
        report.fail("%s.meta: %s" % (rel, "; ".join(problems)))
    else:
        report.ok("%s.meta: plugin for Editor (%s) and Standalone %s, CPU x86_64 only"
                  % (rel, s["editor_os"], s["standalone"]))


PROVENANCE_BEGIN = "<!-- provenance: written by scripts/update_unity_plugins.sh -->"
PROVENANCE_END = "<!-- end of provenance -->"


def source_commit():
    """The last commit that changed what the library is built from."""
    try:
        return subprocess.check_output(
            ["git", "-C", ROOT, "log", "-1", "--format=%H", "--", "native", "include",
             "CMakeLists.txt", "cmake"], stderr=subprocess.DEVNULL).decode().strip() or None
    except Exception:
        return None


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def read_provenance(readme):
    rows = {}
    if not os.path.isfile(readme):
        return rows
    with open(readme, encoding="utf-8") as f:
        for line in f:
            m = re.match(r"^\| `([^`]+)` \| ([0-9a-f]{64}) \| ([^|]+) \| ([0-9a-f]{40}) \|", line)
            if m:
                rows[m.group(1)] = (m.group(2), m.group(3).strip(), m.group(4))
    return rows


def unity_provenance(package):
    """Rewrite the provenance table in Plugins/x86_64/README.md for the plugins present."""
    readme = os.path.join(package, "Plugins", "x86_64", "README.md")
    with open(readme, encoding="utf-8") as f:
        text = f.read()
    commit = source_commit() or "0" * 40
    lines = [PROVENANCE_BEGIN, "",
             "| file | sha256 | version | built from (last commit changing native/, include/, CMake) |",
             "| --- | --- | --- | --- |"]
    for fname in ("libpbf.so", "pbf.dll"):
        path = os.path.join(package, "Plugins", "x86_64", fname)
        if os.path.isfile(path):
            lines.append("| `%s` | %s | %s | %s |" % (fname, sha256(path), header_version(), commit))
    lines += ["", PROVENANCE_END]
    block = "\n".join(lines)
    if PROVENANCE_BEGIN in text:
        text = re.sub(re.escape(PROVENANCE_BEGIN) + r".*?" + re.escape(PROVENANCE_END), block, text, flags=re.S)
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    with open(readme, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
    print("provenance table in %s: %d plugins, source commit %s" % (readme, len(lines) - 6, commit[:12]))
    return 0


SEMVER = re.compile(r"^(0|[1-9]\d*)\.(0|[1-9]\d*)\.(0|[1-9]\d*)(-[0-9A-Za-z.-]+)?(\+[0-9A-Za-z.-]+)?$")


def check_manifest(package, report):
    path = os.path.join(package, "package.json")
    try:
        with open(path, encoding="utf-8") as f:
            m = json.load(f)
    except Exception as e:
        report.fail("package.json: not valid JSON: %s" % e)
        return
    problems = []
    name = m.get("name", "")
    if not re.match(r"^[a-z0-9][a-z0-9_-]*(\.[a-z0-9_-]+)+$", name) or len(name) > 214:
        problems.append("name %r is not a lower-case reverse-domain name" % name)
    version = m.get("version", "")
    if not SEMVER.match(version):
        problems.append("version %r is not semver" % version)
    for key in ("displayName", "description", "unity", "license"):
        if not isinstance(m.get(key), str) or not m.get(key):
            problems.append("%s missing" % key)
    if isinstance(m.get("unity"), str) and not re.match(r"^\d{4}\.\d+$", m["unity"]):
        problems.append("unity %r is not of the form 2021.3" % m["unity"])
    if not isinstance(m.get("author"), dict) or not m["author"].get("name"):
        problems.append("author.name missing")
    for key in ("documentationUrl", "changelogUrl", "licensesUrl"):
        if key in m and not re.match(r"^https?://[^/]+\.[^/]+/", str(m[key])):
            problems.append("%s %r is not an absolute URL" % (key, m[key]))
    for s in m.get("samples", []):
        sp = s.get("path", "")
        if not sp.startswith("Samples~/") or not os.path.isdir(os.path.join(package, sp)):
            problems.append("sample path %r is not a folder under Samples~/" % sp)
        if not s.get("displayName"):
            problems.append("a sample has no displayName")
    for dep, ver in (m.get("dependencies") or {}).items():
        if not SEMVER.match(ver):
            problems.append("dependency %s version %r is not semver" % (dep, ver))
    if problems:
        report.fail("package.json: " + "; ".join(problems))
    else:
        report.ok("package.json: %s %s, licence %s, Unity %s+, %d sample(s)"
                  % (name, version, m["license"], m["unity"], len(m.get("samples", []))))
    hv = header_version()
    if version != hv:
        report.fail("package.json version %s != include/pbf_c_api.h version %s" % (version, hv))
    else:
        report.ok("package.json version %s == header version" % version)


# The last version whose plugins were built without the GPU loader (a CPU-only pbf.dll, a CUDA
# runtime libpbf.so). The committed plugins are refreshed once per release with a version bump;
# from then on they must carry libpbf's kernels like every other build.
LAST_VERSION_WITHOUT_GPU = (2, 0, 0)


def plugin_gpu_rule(path, version):
    """check_native's gpu for a committed plugin: "required", except for a plugin built before the
    GPU went into every binary (of a version up to LAST_VERSION_WITHOUT_GPU and from sources
    without pbf_get_backend_info)."""
    try:
        v = tuple(int(x) for x in version.split("."))
    except ValueError:
        v = (0, 0, 0)
    if v > LAST_VERSION_WITHOUT_GPU or "pbf_get_backend_info" in native_info(path).exports:
        return "required"
    return ("a build of %s, from before libpbf carried the GPU in every binary; required once the plugins are "
            "refreshed with a version bump" % version)


def unity_check(package):
    report = Report("unity package")
    package = os.path.abspath(package)
    print("== Unity package %s" % os.path.relpath(package, ROOT))
    if not os.path.isfile(os.path.join(package, "package.json")):
        report.fail("no package.json")
        return report.close()
    check_manifest(package, report)

    # Files a package ships beside its code.
    for rel in ("CHANGELOG.md", "LICENSE.md"):
        if os.path.isfile(os.path.join(package, rel)):
            report.ok("%s present" % rel)
        else:
            report.fail("%s missing" % rel)
    docs = os.path.join(package, "Documentation~")
    if os.path.isdir(docs) and any(f.endswith(".md") for f in os.listdir(docs)):
        report.ok("Documentation~ holds %s" % ", ".join(sorted(f for f in os.listdir(docs) if f.endswith(".md"))))
    else:
        report.fail("Documentation~/ with a .md file missing")
    repo_license = os.path.join(ROOT, "LICENSE")
    if os.path.isfile(repo_license) and os.path.isfile(os.path.join(package, "LICENSE.md")):
        with open(repo_license, encoding="utf-8") as a, open(os.path.join(package, "LICENSE.md"), encoding="utf-8") as b:
            if a.read().strip() == b.read().strip():
                report.ok("LICENSE.md is the repository's LICENSE")
            else:
                report.fail("LICENSE.md differs from the repository's LICENSE")
    elif not os.path.isfile(repo_license):
        report.warn("no LICENSE at the repository root to compare LICENSE.md with")

    # .meta files: one per asset, none orphaned, well-formed, unique GUIDs, the right importer.
    guids = {}
    for root in asset_roots(package):
        where = os.path.relpath(root, package)
        assets, metas = unity_assets(root)
        asset_set = {rel for rel, _ in assets}
        missing = [rel for rel, _ in assets if not os.path.isfile(os.path.join(root, rel) + ".meta")]
        orphans = [m for m in metas if m[:-5] not in asset_set]
        label = "package" if where == "." else where
        if missing:
            report.fail("%s: %d assets without a .meta (Unity would skip or re-GUID them): %s"
                        % (label, len(missing), ", ".join(missing[:6])))
        else:
            report.ok("%s: all %d files and folders have a .meta" % (label, len(assets)))
        if orphans:
            report.fail("%s: .meta files without an asset: %s" % (label, ", ".join(orphans[:6])))
        else:
            report.ok("%s: no orphan .meta" % label)
        bad = []
        for rel, is_dir in assets:
            meta = os.path.join(root, rel) + ".meta"
            if not os.path.isfile(meta):
                continue
            with open(meta, encoding="utf-8") as f:
                text = f.read()
            shown = os.path.relpath(os.path.join(root, rel), package)
            g = re.search(r"^guid: (\S+)\s*$", text, flags=re.M)
            if not text.startswith("fileFormatVersion: 2\n") or not g:
                bad.append("%s.meta: no 'fileFormatVersion: 2' / 'guid:' header" % shown)
                continue
            guid = g.group(1)
            if not re.match(r"^[0-9a-f]{32}$", guid):
                bad.append("%s.meta: guid %r is not 32 lower-case hex digits" % (shown, guid))
            elif guid in guids:
                bad.append("%s.meta: guid %s already used by %s" % (shown, guid, guids[guid]))
            else:
                guids[guid] = shown
            if is_dir != bool(re.search(r"^folderAsset: yes$", text, flags=re.M)):
                bad.append("%s.meta: folderAsset %s" % (shown, "missing" if is_dir else "set on a file"))
            want = importer_for(rel, is_dir)
            want = "DefaultImporter" if want == "folder" else want
            if not re.search(r"^%s:$" % want, text, flags=re.M):
                bad.append("%s.meta: expected %s" % (shown, want))
            if want == "PluginImporter":
                check_plugin_meta(shown, text, report)
        if bad:
            report.fail("%s: %s" % (label, "; ".join(bad[:6]) + (" (+%d more)" % (len(bad) - 6) if len(bad) > 6 else "")))
        else:
            report.ok("%s: every .meta well-formed, importer matches the file type, GUIDs unique" % label)

    # A git-URL install gets what git has: nothing Unity imports may be ignored by git, and all of
    # it should be committed.
    try:
        def git_list(*extra):
            out = subprocess.check_output(["git", "-C", package, "ls-files", "--others", "--exclude-standard"]
                                          + list(extra) + ["--", "."], stderr=subprocess.DEVNULL)
            return [l for l in out.decode().splitlines() if l]
        ignored = [f for f in git_list("--ignored") if not any(
            unity_ignored(part) for part in f.split("/")[:-1] + [os.path.basename(f)[:-5] if f.endswith(".meta") else os.path.basename(f)])]
        untracked = git_list()
        if ignored:
            report.fail("git ignores files of the package, so a git-URL install lacks them: %s" % ", ".join(ignored[:6]))
        else:
            report.ok("git ignores none of the package's files")
        if untracked:
            report.warn("not committed yet: %s" % ", ".join(untracked[:6]))
    except (subprocess.CalledProcessError, OSError):
        report.note("not in a git work tree: git's view of the package not checked")

    # Scenes and materials refer to assets by GUID: each must be one the package ships, or Unity's.
    for root in asset_roots(package):
        for rel, is_dir in unity_assets(root)[0]:
            if is_dir or not rel.endswith((".unity", ".mat", ".prefab")):
                continue
            with open(os.path.join(root, rel), encoding="utf-8") as f:
                refs = set(re.findall(r"guid: ([0-9a-f]{32})", f.read()))
            builtin = {"0000000000000000e000000000000000", "0000000000000000f000000000000000"}
            unknown = sorted(refs - set(guids) - builtin)
            shown = os.path.relpath(os.path.join(root, rel), package)
            if unknown:
                report.fail("%s refers to GUIDs the package does not ship: %s" % (shown, ", ".join(unknown)))
            else:
                report.ok("%s: its %d GUID references resolve" % (shown, len(refs)))

    # Assembly definition.
    asmdefs = [rel for rel, d in unity_assets(package)[0] if rel.endswith(".asmdef")]
    for rel in asmdefs:
        try:
            with open(os.path.join(package, rel), encoding="utf-8") as f:
                a = json.load(f)
            report.ok("%s: assembly %s" % (rel, a["name"]))
        except Exception as e:
            report.fail("%s: %s" % (rel, e))
    if not asmdefs:
        report.fail("no .asmdef: the scripts would land in Assembly-CSharp")

    # Native plugins: present, right format, exports == header, version, provenance.
    plugdir = os.path.join(package, "Plugins", "x86_64")
    prov = read_provenance(os.path.join(plugdir, "README.md"))
    require_windows = os.environ.get("PBF_UNITY_REQUIRE_WINDOWS", "1") != "0"
    strict = os.environ.get("PBF_UNITY_STRICT", "0") == "1"
    current = source_commit()
    infos = []
    for fname, kind in (("libpbf.so", "linux-x64"), ("pbf.dll", "win-x64")):
        path = os.path.join(plugdir, fname)
        if not os.path.isfile(path):
            msg = "Plugins/x86_64/%s missing (refresh with scripts/update_unity_plugins.sh)" % fname
            if kind == "win-x64" and not require_windows:
                report.warn(msg + "; PBF_UNITY_REQUIRE_WINDOWS=0, so the package is Linux-only")
            else:
                report.fail(msg)
            continue
        row = prov.get(fname)
        infos.append((fname, check_native(path, kind, report, plugin_gpu_rule(path, row[1] if row else header_version()))))
        if kind == "linux-x64":
            v = loaded_version(path)
            if v == header_version():
                report.ok("Plugins/x86_64/%s: pbf_get_version() = %s, the header's" % (fname, v))
            else:
                report.fail("Plugins/x86_64/%s: pbf_get_version() = %s, header %s: refresh the plugins"
                            % (fname, v, header_version()))
        if not row:
            report.fail("Plugins/x86_64/%s: no provenance row in Plugins/x86_64/README.md" % fname)
            continue
        if row[0] != sha256(path):
            report.fail("Plugins/x86_64/%s: sha256 differs from its provenance row (copied by hand?)" % fname)
        else:
            report.ok("Plugins/x86_64/%s: sha256 matches its provenance row (built from %s)" % (fname, row[2][:12]))
        if row[1] != header_version():
            report.fail("Plugins/x86_64/%s: provenance says version %s, header %s" % (fname, row[1], header_version()))
        if current and row[2] != current:
            msg = ("Plugins/x86_64/%s was built from %s, but native/ include/ or CMake changed since (%s): "
                   "refresh with scripts/update_unity_plugins.sh" % (fname, row[2][:12], current[:12]))
            if strict:
                report.fail(msg)
            else:
                report.warn(msg + " (PBF_UNITY_STRICT=1 makes this a failure)")
    check_same_kernels(infos, report)
    return report.close()


def unity_selftest(package):
    """Breaks copies of the package one way at a time; the check must fail on each."""
    import contextlib
    import io
    import shutil
    import tempfile
    package = os.path.abspath(package)
    report = Report("unity check self-test")
    print("== self-test: the Unity package check must fail on each of these broken copies")

    def first(pattern):
        for dirpath, _, files in os.walk(package):
            for f in sorted(files):
                if re.search(pattern, f):
                    return os.path.relpath(os.path.join(dirpath, f), package)
        raise SystemExit("self-test: no file matches %s" % pattern)

    def drop(rel):
        return lambda d: os.remove(os.path.join(d, rel))

    def edit(rel, old, new):
        def f(d):
            path = os.path.join(d, rel)
            with open(path, encoding="utf-8") as fh:
                text = fh.read()
            assert old in text, (rel, old)
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text.replace(old, new, 1))
        return f

    def add(rel, text):
        def f(d):
            with open(os.path.join(d, rel), "w", encoding="utf-8") as fh:
                fh.write(text)
        return f

    cs = first(r"^World\.cs$")
    so_meta = "Plugins/x86_64/libpbf.so.meta"
    with open(os.path.join(package, cs + ".meta"), encoding="utf-8") as fh:
        cs_guid = re.search(r"^guid: (\S+)", fh.read(), flags=re.M).group(1)
    cases = [
        ("a script without its .meta", drop(cs + ".meta")),
        ("a folder without its .meta", drop("Runtime/Core.meta")),
        ("a new file without a .meta", add("Runtime/Extra.cs", "class Extra {}\n")),
        ("an orphan .meta", add("Runtime/Gone.cs.meta", "fileFormatVersion: 2\nguid: 0123456789abcdef0123456789abcdef\n")),
        ("a duplicated GUID", edit("Runtime/PbfUnity.cs.meta", re.search(r"guid: \S+", open(os.path.join(package, "Runtime/PbfUnity.cs.meta")).read()).group(0), "guid: " + cs_guid)),
        ("a malformed GUID", edit(cs + ".meta", "guid: " + cs_guid, "guid: " + cs_guid[:31] + "g")),
        ("a folder .meta without folderAsset", edit("Runtime.meta", "folderAsset: yes\n", "")),
        ("the Linux plugin enabled for Windows", edit(so_meta, "      Standalone: Win64\n    second:\n      enabled: 0", "      Standalone: Win64\n    second:\n      enabled: 1")),
        ("the Linux plugin's editor OS set to Windows", edit(so_meta, "OS: Linux", "OS: Windows")),
        ("the Linux plugin for CPU x86", edit(so_meta, "      Standalone: Linux64\n    second:\n      enabled: 1\n      settings:\n        CPU: x86_64", "      Standalone: Linux64\n    second:\n      enabled: 1\n      settings:\n        CPU: x86")),
        ("the Linux plugin missing", drop("Plugins/x86_64/libpbf.so")),
        ("the Linux plugin replaced by another file", add("Plugins/x86_64/libpbf.so", "not a library\n")),
        ("package.json not JSON", edit("package.json", "{", "{,")),
        ("package.json without a licence", edit("package.json", '"license": "MIT",', "")),
        ("package.json at another version", edit("package.json", '"version": "', '"version": "0.0.1-')),
        ("package.json with a relative URL", edit("package.json", '"license": "MIT",', '"license": "MIT", "documentationUrl": "../README.md",')),
        ("CHANGELOG.md missing", drop("CHANGELOG.md")),
        ("the sample scene referring to a missing asset", edit("Samples~/FluidDemo/FluidDemo.unity", "guid: ", "guid: 0")),
        ("a sample file without its .meta", drop("Samples~/FluidDemo/PbfFluidDemo.cs.meta")),
    ]
    env_before = dict(os.environ)
    os.environ["PBF_UNITY_REQUIRE_WINDOWS"] = "0"   # the one optional part: not what is tested here
    try:
        for name, breakit in cases:
            with tempfile.TemporaryDirectory() as tmp:
                copy = os.path.join(tmp, "pkg")
                shutil.copytree(package, copy)
                try:
                    breakit(copy)
                except Exception as e:
                    report.fail("%s: could not break the copy (%s)" % (name, e))
                    continue
                out = io.StringIO()
                with contextlib.redirect_stdout(out):
                    rc = unity_check(copy)
                fails = [l.strip()[6:] for l in out.getvalue().splitlines() if l.startswith("  FAIL")]
                # The unbroken package's own failures (e.g. a version mismatch) do not count.
                new = [f for f in fails if f not in baseline]
                if rc != 0 and new:
                    report.ok("%s: caught (%s)" % (name, new[0][:110]))
                else:
                    report.fail("%s: NOT caught" % name)
    finally:
        os.environ.clear()
        os.environ.update(env_before)
    return report.close()


def _baseline_failures(package):
    import contextlib
    import io
    out = io.StringIO()
    old = os.environ.get("PBF_UNITY_REQUIRE_WINDOWS")
    os.environ["PBF_UNITY_REQUIRE_WINDOWS"] = "0"
    with contextlib.redirect_stdout(out):
        unity_check(package)
    if old is None:
        del os.environ["PBF_UNITY_REQUIRE_WINDOWS"]
    else:
        os.environ["PBF_UNITY_REQUIRE_WINDOWS"] = old
    return {l.strip()[6:] for l in out.getvalue().splitlines() if l.startswith("  FAIL")}


def native_selftest(so, dll):
    """Breaks copies of a libpbf.so and a pbf.dll built with CUDA one way at a time: the native
    checks must fail on each."""
    import contextlib
    import io
    import shutil
    import tempfile
    report = Report("native check self-test")
    print("== self-test: the native library checks must fail on each of these broken copies")

    def patch(old, new, where=None):
        def f(data, info):
            start = data.find(old) if where is None else where(data, info)
            assert start >= 0, old
            data[start:start + len(new)] = new
        return f

    def in_fatbin(offset):
        return lambda data, info: info.fatbin["offset"] + offset

    cases = [
        ("libpbf.so without the fatbin's magic", "so", patch(None, b"\0\0\0\0", in_fatbin(0))),
        ("pbf.dll without the fatbin's magic", "dll", patch(None, b"\0\0\0\0", in_fatbin(0))),
        ("libpbf.so needing libcuda", "so", patch(b"libm.so.6\0", b"libcuda.1\0")),
        ("pbf.dll importing nvcuda.dll", "dll", patch(b"msvcrt.dll\0", b"nvcuda.dll\0")),
        ("pbf.dll with other kernels than libpbf.so", "dll", patch(None, b"\xA5", in_fatbin(4096))),
    ]
    sources = {"so": os.path.abspath(so), "dll": os.path.abspath(dll)}
    lacking = [p for p in sources.values() if not os.path.isfile(p) or not native_info(p).fatbin]
    if lacking:
        print("native check self-test: skipped (%s: no build with the CUDA kernels)" % ", ".join(lacking))
        return 77
    for name, which, breakit in cases:
        with tempfile.TemporaryDirectory() as tmp:
            paths = {}
            for k, src in sources.items():
                paths[k] = os.path.join(tmp, os.path.basename(src))
                shutil.copyfile(src, paths[k])
            with open(paths[which], "rb") as f:
                data = bytearray(f.read())
            try:
                breakit(data, native_info(paths[which]))
            except Exception as e:
                report.fail("%s: could not break the copy (%s)" % (name, e))
                continue
            with open(paths[which], "wb") as f:
                f.write(data)
            out = io.StringIO()
            checked = Report("native")
            with contextlib.redirect_stdout(out):
                infos = [(k, check_native(paths[k], {"so": "linux-x64", "dll": "win-x64"}[k], checked)) for k in ("so", "dll")]
                check_same_kernels(infos, checked)
            fails = [l.strip()[6:] for l in out.getvalue().splitlines() if l.startswith("  FAIL")]
            if fails:
                report.ok("%s: caught (%s)" % (name, fails[0][:110]))
            else:
                report.fail("%s: NOT caught" % name)
    return report.close()


# ---------------------------------------------------------------------------------------------
# NuGet


NUSPEC_NS = "http://schemas.microsoft.com/packaging/2013/05/nuspec.xsd"


def nupkg(nuspec, basedir, outdir, optional=()):
    """Assemble a .nupkg: a zip in the Open Packaging Conventions layout that 'nuget pack' writes
    ([Content_Types].xml, _rels/.rels, the nuspec without <files>, a core-properties part) plus the
    files the nuspec's <files> lists. For nuget 2.8, which cannot read <license> (NuGet 4.9+)."""
    ET.register_namespace("", NUSPEC_NS)
    tree = ET.parse(nuspec)
    pkg = tree.getroot()
    ns = {"n": NUSPEC_NS}
    md = pkg.find("n:metadata", ns)
    pid, version = md.find("n:id", ns).text, md.find("n:version", ns).text
    files = pkg.find("n:files", ns)
    entries = []
    for f in (files if files is not None else []):
        src = os.path.join(basedir, f.get("src"))
        if not os.path.isfile(src) and f.get("target") in optional:
            print("nupkg: WARNING: %s is missing: the package goes without %s" % (src, f.get("target")), file=sys.stderr)
            continue
        if not os.path.isfile(src):
            print("nupkg: %s (from %s) does not exist" % (src, nuspec), file=sys.stderr)
            return 1
        entries.append((src, f.get("target")))
    if files is not None:
        pkg.remove(files)
    spec_xml = ET.tostring(pkg, encoding="unicode")
    os.makedirs(outdir, exist_ok=True)
    out = os.path.join(outdir, "%s.%s.nupkg" % (pid, version))
    props_name = "package/services/metadata/core-properties/%s.psmdcp" % uuid.uuid5(uuid.NAMESPACE_URL, pid + version).hex
    exts = sorted({os.path.splitext(t)[1].lstrip(".").lower() for _, t in entries if os.path.splitext(t)[1]})
    types = ['<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml" />',
             '<Default Extension="nuspec" ContentType="application/octet" />',
             '<Default Extension="psmdcp" ContentType="application/vnd.openxmlformats-package.core-properties+xml" />']
    types += ['<Default Extension="%s" ContentType="application/octet" />' % e for e in exts if e not in ("rels", "nuspec", "psmdcp")]
    content_types = ('<?xml version="1.0" encoding="utf-8"?>\n<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
                     + "".join(types) + "</Types>")
    rels = ('<?xml version="1.0" encoding="utf-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
            '<Relationship Type="http://schemas.microsoft.com/packaging/2010/07/manifest" Target="/%s.nuspec" Id="R1" />'
            '<Relationship Type="http://schemas.openxmlformats.org/package/2006/relationships/metadata/core-properties" Target="/%s" Id="R2" />'
            "</Relationships>") % (pid, props_name)
    desc = md.find("n:description", ns)
    authors = md.find("n:authors", ns)
    props = ('<?xml version="1.0" encoding="utf-8"?>\n<coreProperties xmlns:dc="http://purl.org/dc/elements/1.1/" '
             'xmlns:dcterms="http://purl.org/dc/terms/" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
             'xmlns="http://schemas.openxmlformats.org/package/2006/metadata/core-properties">'
             "<dc:creator>%s</dc:creator><dc:description>%s</dc:description><dc:identifier>%s</dc:identifier>"
             "<version>%s</version><keywords></keywords><lastModifiedBy>scripts/pack_nuget.sh</lastModifiedBy>"
             "</coreProperties>") % (_xml(authors.text if authors is not None else ""),
                                     _xml(desc.text if desc is not None else ""), _xml(pid), _xml(version))
    if os.path.exists(out):
        os.remove(out)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("_rels/.rels", rels)
        z.writestr("%s.nuspec" % pid, '<?xml version="1.0" encoding="utf-8"?>\n' + spec_xml)
        for src, target in entries:
            z.write(src, target.replace("\\", "/"))
        z.writestr(props_name, props)
        z.writestr("[Content_Types].xml", content_types)
    print(out)
    return 0


def _xml(s):
    return (s or "").replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def nupkg_check(path):
    report = Report("nuget package contents")
    print("== NuGet package %s" % os.path.relpath(os.path.abspath(path), ROOT))
    with zipfile.ZipFile(path) as z:
        names = set(z.namelist())
        specs = [n for n in names if n.endswith(".nuspec") and "/" not in n]
        if len(specs) != 1:
            report.fail("expected one .nuspec at the root, found %s" % specs)
            return report.close()
        md = ET.fromstring(z.read(specs[0])).find("{%s}metadata" % NUSPEC_NS)
        get = lambda k: (md.find("{%s}%s" % (NUSPEC_NS, k)).text if md.find("{%s}%s" % (NUSPEC_NS, k)) is not None else None)
        lic = md.find("{%s}license" % NUSPEC_NS)
        version = get("version")
        if lic is not None and lic.get("type") == "expression" and lic.text == "MIT":
            report.ok("licence expression MIT")
        else:
            report.fail("no <license type=\"expression\">MIT</license>")
        if version == header_version():
            report.ok("%s %s == header version" % (get("id"), version))
        else:
            report.fail("nuspec version %s != header version %s" % (version, header_version()))
        for part in ("[Content_Types].xml", "_rels/.rels"):
            (report.ok if part in names else report.fail)("%s %s" % (part, "present" if part in names else "missing"))
        if "lib/netstandard2.1/Pbf.dll" in names:
            report.ok("lib/netstandard2.1/Pbf.dll present")
        else:
            report.fail("lib/netstandard2.1/Pbf.dll missing")
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            infos = []
            for entry, kind in (("runtimes/linux-x64/native/libpbf.so", "linux-x64"),
                                ("runtimes/win-x64/native/pbf.dll", "win-x64")):
                if entry not in names:
                    msg = "%s missing" % entry
                    if kind == "win-x64" and os.environ.get("PBF_NUGET_REQUIRE_WINDOWS", "1") == "0":
                        report.warn(msg + ": this package is Linux-only (PBF_NUGET_REQUIRE_WINDOWS=0)")
                    else:
                        report.fail(msg)
                    continue
                z.extract(entry, tmp)
                # The package ships the GPU: PBF_NUGET_REQUIRE_GPU=0 accepts CPU-only builds (a
                # machine without nvcc), with a warning.
                gpu = "required" if os.environ.get("PBF_NUGET_REQUIRE_GPU", "1") != "0" else "PBF_NUGET_REQUIRE_GPU=0"
                infos.append((entry, check_native(os.path.join(tmp, entry), kind, _Prefixed(report, entry), gpu)))
            check_same_kernels(infos, report)
    return report.close()


class _Prefixed(object):
    """Shows the package entry's name instead of a temporary path."""
    def __init__(self, report, entry):
        self.r, self.entry = report, entry

    def _m(self, msg):
        return re.sub(r"^[^:]*:", self.entry + ":", msg, count=1)

    def ok(self, msg): self.r.ok(self._m(msg))
    def fail(self, msg): self.r.fail(self._m(msg))
    def warn(self, msg): self.r.warn(self._m(msg))
    def note(self, msg): self.r.note(self._m(msg))


# ---------------------------------------------------------------------------------------------


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(argv) >= 2 else 2
    cmd, args = argv[1], argv[2:]
    if cmd == "header-version":
        print(header_version())
    elif cmd == "header-functions":
        print("\n".join(sorted(header_functions())))
    elif cmd == "exports":
        print("\n".join(sorted(native_info(args[0]).exports)))
    elif cmd == "deps":
        print("\n".join(native_info(args[0]).needed))
    elif cmd == "check-native":
        r = Report("native")
        check_native(os.path.abspath(args[0]), args[1], r, args[2] if len(args) > 2 else "required")
        return r.close()
    elif cmd == "native-selftest":
        return native_selftest(args[0], args[1])
    elif cmd == "unity-metas":
        return unity_metas(os.path.abspath(args[0]), "--write" in args)
    elif cmd == "unity-check":
        return unity_check(args[0])
    elif cmd == "unity-selftest":
        global baseline
        baseline = _baseline_failures(os.path.abspath(args[0]))
        return unity_selftest(args[0])
    elif cmd == "unity-provenance":
        return unity_provenance(os.path.abspath(args[0]))
    elif cmd == "nupkg":
        opt = [args[i + 1] for i in range(3, len(args) - 1) if args[i] == "--optional"]
        return nupkg(args[0], args[1], args[2], opt)
    elif cmd == "nupkg-check":
        return nupkg_check(args[0])
    else:
        print("unknown command %r\n%s" % (cmd, __doc__), file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
