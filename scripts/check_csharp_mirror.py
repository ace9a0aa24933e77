#!/usr/bin/env python3
"""The C# mirror against include/pbf_c_api.h, by name, without building anything:

  python3 scripts/check_csharp_mirror.py

1. every PBF_API function of the header has a DllImport in Native.cs, and Native.cs imports
   nothing the header lacks;
2. every struct, field, enum constant and numeric PBF_* macro of the header is listed in
   bindings/csharp/tools/layout_dump.c: the dump bindings/csharp/tests/LayoutTests.cs compares,
   size by size and value by value, with the C# mirror. A header addition missing from the dump
   would otherwise go unchecked;
3. every pbf_buffer kind has a member of the friendly BufferSource enum (by value);
4. every field of every *_desc and *_params struct is reached by the friendly layer (a `.field`
   access in Runtime/Core outside Native.cs), but for the raw-only structs and fields below.

Then it checks itself: on a copy of the header with a new function, a new world desc field and a
new buffer kind it must fail (at least three checks).

Ends with 'csharp mirror: N passed, N failed'; exit 1 on any failure.
"""
import contextlib
import io
import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pbf_packages as P  # noqa: E402  (the header parser the package checks use)

CORE = os.path.join(P.ROOT, "bindings", "csharp", "unity", "Runtime", "Core")
DUMP = os.path.join(P.ROOT, "bindings", "csharp", "tools", "layout_dump.c")
# Macros that are not values: the include guard and the export/calling-convention decorations.
NOT_VALUES = {"PBF_C_API_H", "PBF_API", "PBF_CALL"}
# External memory and semaphores are raw-layer only (bindings/csharp/README.md says so); a desc's
# struct_size, reserved fields and header_version are filled by the bindings' *_desc_init calls.
RAW_ONLY_STRUCTS = {"pbf_external_buffer_desc", "pbf_semaphore_desc"}
SET_BY_INIT = {"struct_size", "header_version"}


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
    """Adds the checks above to report."""
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

    sources, friendly_layer = "", ""
    for name in sorted(os.listdir(CORE)):
        if name.endswith(".cs"):
            with open(os.path.join(CORE, name), encoding="utf-8") as f:
                text_cs = f.read()
            sources += text_cs
            if name != "Native.cs":
                friendly_layer += text_cs
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

    descs = {n: f for n, f in structs.items() if n.endswith(("_desc", "_params")) and n not in RAW_ONLY_STRUCTS}
    missing = ["%s.%s" % (n, f) for n, fs in sorted(descs.items()) for f in fs
               if f not in SET_BY_INIT and not f.startswith("reserved") and not re.search(r"\.%s\b" % f, friendly_layer)]
    if missing:
        report.fail("the friendly layer never sets or reads: %s" % ", ".join(missing))
    else:
        report.ok("the friendly layer reaches every field of the header's %d desc and params structs "
                  "(raw only: %s)" % (len(descs), ", ".join(sorted(RAW_ONLY_STRUCTS))))


def selftest(report):
    """The check on a header that gained a function, a world desc field and a buffer kind."""
    with open(P.HEADER, encoding="utf-8") as f:
        text = f.read()
    broken = text.replace("PBF_API pbf_result PBF_CALL pbf_world_step(",
                          "PBF_API pbf_result PBF_CALL pbf_world_selftest_call(pbf_world_id world);\n"
                          "PBF_API pbf_result PBF_CALL pbf_world_step(", 1)
    broken = re.sub(r"(typedef struct pbf_world_desc \{.*?)(\} pbf_world_desc;)", r"\1    uint32_t selftest_field;\n\2",
                    broken, count=1, flags=re.S)
    broken = broken.replace("PBF_BUFFER_FORCE32 = 0x7FFFFFFF", "PBF_BUFFER_SELFTEST = 99,\n    PBF_BUFFER_FORCE32 = 0x7FFFFFFF", 1)
    real = P.HEADER
    with tempfile.TemporaryDirectory() as tmp:
        P.HEADER = os.path.join(tmp, "pbf_c_api.h")
        with open(P.HEADER, "w", encoding="utf-8") as f:
            f.write(broken)
        inner = P.Report("csharp mirror self-test")
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                check(inner)
        finally:
            P.HEADER = real
    if broken != text and inner.failed >= 3:
        report.ok("self-test: fails (%d times) on a header with a new function, desc field and buffer kind" % inner.failed)
    else:
        report.fail("self-test: a header with a new function, desc field and buffer kind failed only %d checks" % inner.failed)


def main():
    print("== C# mirror of %s" % os.path.relpath(P.HEADER, P.ROOT))
    report = P.Report("csharp mirror")
    check(report)
    selftest(report)
    return report.close()


if __name__ == "__main__":
    sys.exit(main())
