#!/usr/bin/env python3
"""The C# mirror against include/pbf_c_api.h, by name, without building anything:

  python3 scripts/check_csharp_mirror.py

1. every PBF_API function of the header has a DllImport in Native.cs, and Native.cs imports
   nothing the header lacks;
2. every struct, field, enum constant and numeric PBF_* macro of the header is listed in
   bindings/csharp/tools/layout_dump.c: the dump bindings/csharp/tests/LayoutTests.cs compares,
   size by size and value by value, with the C# mirror. A header addition missing from the dump
   would otherwise go unchecked;
3. every pbf_buffer kind has a member of the friendly BufferSource enum (by value).

Ends with 'csharp mirror: N passed, N failed'; exit 1 on any failure.
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pbf_packages as P  # noqa: E402  (the header parser the package checks use)

CORE = os.path.join(P.ROOT, "bindings", "csharp", "unity", "Runtime", "Core")
DUMP = os.path.join(P.ROOT, "bindings", "csharp", "tools", "layout_dump.c")
# Macros that are not values: the include guard and the export/calling-convention decorations.
NOT_VALUES = {"PBF_C_API_H", "PBF_API", "PBF_CALL"}


def header_structs(text):
    """{struct: [field, ...]} of every 'typedef struct X { ... } X;'."""
    out = {}
    for m in re.finditer(r"typedef\s+struct\s+\w+\s*\{(.*?)\}\s*(\w+)\s*;", text, re.S):
        fields = []
        for decl in m.group(1).split(";"):
            decl = decl.strip()
            if decl:
                fields.append(re.search(r"(\w+)\s*(\[[^\]]*\])?\s*$", decl).group(1))
        out[m.group(2)] = fields
    return out


def header_enums(text):
    """{enum: [constant, ...]} of every 'typedef enum X { ... } X;'."""
    out = {}
    for m in re.finditer(r"typedef\s+enum\s+\w+\s*\{(.*?)\}\s*(\w+)\s*;", text, re.S):
        out[m.group(2)] = [re.match(r"\s*(\w+)", e).group(1) for e in m.group(1).split(",") if e.strip()]
    return out


def header_buffer_values(text):
    m = re.search(r"typedef\s+enum\s+pbf_buffer\s*\{(.*?)\}", text, re.S)
    return {name: int(value, 0) for name, value in re.findall(r"(\w+)\s*=\s*(0x[0-9A-Fa-f]+|\d+)", m.group(1))}


def header_macros(text):
    """Object-like PBF_* macros with a value (function-like ones have '(' after the name)."""
    names = re.findall(r"#\s*define\s+(PBF_\w+)[ \t]+\S", text)
    return sorted(set(names) - NOT_VALUES)


def csharp_imports(native_cs):
    return set(re.findall(r"static\s+extern\s+[\w.\[\]]+\s+(pbf_\w+)\s*\(", native_cs))


def csharp_enum_values(source, name):
    m = re.search(r"enum\s+%s\b[^{]*\{(.*?)\}" % name, source, re.S)
    if not m:
        return None
    return {v: int(n, 0) for v, n in re.findall(r"(\w+)\s*=\s*(0x[0-9A-Fa-f]+|\d+)", m.group(1))}


def check(report):
    text = P._header_text()
    with open(os.path.join(CORE, "Native.cs"), encoding="utf-8") as f:
        native_cs = f.read()
    with open(DUMP, encoding="utf-8") as f:
        dump = f.read()

    want, have = P.header_functions(), csharp_imports(native_cs)
    if want - have:
        report.fail("Native.cs lacks DllImports of: %s" % ", ".join(sorted(want - have)))
    else:
        report.ok("Native.cs imports all %d functions of the header" % len(want))
    if have - want:
        report.fail("Native.cs imports functions the header does not declare: %s" % ", ".join(sorted(have - want)))
    else:
        report.ok("Native.cs imports nothing the header lacks")

    structs = header_structs(text)
    missing = [s for s in structs if "STRUCT(%s)" % s not in dump]
    missing += ["%s.%s" % (s, f) for s, fs in structs.items() for f in fs if "FIELD(%s, %s)" % (s, f) not in dump]
    if missing:
        report.fail("layout_dump.c lacks (so LayoutTests cannot compare them): %s" % ", ".join(missing))
    else:
        report.ok("layout_dump.c lists all %d structs and %d fields of the header"
                  % (len(structs), sum(len(f) for f in structs.values())))

    enums = header_enums(text)
    missing = ["%s.%s" % (e, c) for e, cs in enums.items() for c in cs if "ENUM(%s, %s)" % (e, c) not in dump]
    if missing:
        report.fail("layout_dump.c lacks enum constants: %s" % ", ".join(missing))
    else:
        report.ok("layout_dump.c lists all %d constants of the header's %d enums"
                  % (sum(len(c) for c in enums.values()), len(enums)))

    macros = header_macros(text)
    missing = [m for m in macros if "CONST(%s)" % m not in dump]
    if missing:
        report.fail("layout_dump.c lacks the macros: %s" % ", ".join(missing))
    else:
        report.ok("layout_dump.c lists all %d PBF_* value macros of the header" % len(macros))

    sources = ""
    for name in sorted(os.listdir(CORE)):
        if name.endswith(".cs"):
            with open(os.path.join(CORE, name), encoding="utf-8") as f:
                sources += f.read()
    friendly = csharp_enum_values(sources, "BufferSource")
    kinds = {n: v for n, v in header_buffer_values(text).items() if not n.endswith("FORCE32")}
    if friendly is None:
        report.fail("no BufferSource enum in the bindings")
    else:
        lacking = [n for n, v in sorted(kinds.items()) if v not in friendly.values()]
        if lacking:
            report.fail("BufferSource has no member for: %s" % ", ".join(lacking))
        else:
            report.ok("BufferSource has a member for each of the header's %d buffer kinds" % len(kinds))
    return report.close()


def main():
    print("== C# mirror of %s" % os.path.relpath(P.HEADER, P.ROOT))
    return check(P.Report("csharp mirror"))


if __name__ == "__main__":
    sys.exit(main())
