#!/usr/bin/env python3
"""The C# bindings against include/pbf_c_api.h, without building anything:

  python3 scripts/check_csharp_mirror.py

1. the generated raw layer (Native.cs) and layout dump (tools/layout_dump.c) are what
   scripts/gen_csharp_bindings.py makes of the header now: a header change without a
   regenerated mirror fails here (bindings/csharp/tests/LayoutTests.cs then compares the dump,
   size by size and value by value, with the C# mirror);
2. every pbf_buffer kind has a member of the friendly BufferSource enum (by value);
3. every field of every *_desc and *_params struct is reached by the friendly layer (a `.field`
   access in Runtime/Core outside the generated Native.cs), but for the raw-only structs and
   fields below.

Then it checks itself: on a copy of the header with a new function, a new world desc field and a
new buffer kind it must fail (three checks); and the generator must carry a new struct (fixed
char and byte arrays, a nested struct) and a function taking it into both generated files.

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
import gen_csharp_bindings as G  # noqa: E402

CORE = os.path.join(P.ROOT, "bindings", "csharp", "unity", "Runtime", "Core")
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


def header_buffer_values(text):
    m = re.search(r"typedef\s+enum\s+pbf_buffer\s*\{(.*?)\}", text, re.S)
    return {name: int(value, 0) for name, value in re.findall(r"(\w+)\s*=\s*(0x[0-9A-Fa-f]+|\d+)", m.group(1))}


def csharp_enum_values(source, name):
    m = re.search(r"enum\s+%s\b[^{]*\{(.*?)\}" % name, source, re.S)
    if not m:
        return None
    return {v: int(n, 0) for v, n in re.findall(r"(\w+)\s*=\s*(0x[0-9A-Fa-f]+|\d+)", m.group(1))}


def check(report):
    """Adds the checks above to report."""
    text = P._header_text()
    stale = G.stale(G.generate(P.HEADER))
    if stale:
        report.fail("the generated bindings differ from what %s makes of the header "
                    "(run python3 scripts/gen_csharp_bindings.py):\n%s"
                    % (os.path.relpath(P.HEADER, P.ROOT), "".join(d for _, d in stale)[:4000]))
    else:
        report.ok("Native.cs and tools/layout_dump.c are generated from the header as it is "
                  "(scripts/gen_csharp_bindings.py --check)")
    structs = header_structs(text)

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
    generator_selftest(report, text)


NEW_DECLS = """
typedef struct pbf_selftest_info {
    uint32_t struct_size;
    uint32_t available;         /* selftest field doc */
    char name[32];
    char device_name[128];
    uint8_t uuid[16];
    pbf_world_id world;
    float origin[3];
} pbf_selftest_info;
/* selftest function doc */
PBF_API pbf_result PBF_CALL pbf_get_selftest_info(pbf_backend backend, pbf_selftest_info* out_info);
"""


def generator_selftest(report, text):
    """A struct of fixed arrays and a nested struct, and a function that fills it, added to the
    header, reach both generated files with no change to the generator."""
    anchor = "PBF_API pbf_result PBF_CALL pbf_world_step("
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "pbf_c_api.h")
        with open(path, "w", encoding="utf-8") as f:
            f.write(text.replace(anchor, NEW_DECLS + anchor, 1))
        files = G.generate(path)
    cs, dump = files[G.NATIVE_CS], files[G.LAYOUT_DUMP]
    want_cs = ["public struct pbf_selftest_info", "public uint available;", "public Char32 name;",
               "public Char128 device_name;", "public Bytes16 uuid;", "public pbf_world_id world;",
               "public Float3 origin;", "public struct Char32", "/// <summary>selftest field doc</summary>",
               "/// <summary>selftest function doc</summary>",
               "pbf_get_selftest_info(pbf_backend backend, ref pbf_selftest_info out_info);",
               "pbf_get_selftest_info(pbf_backend backend, IntPtr out_info);"]
    want_dump = ["STRUCT(pbf_selftest_info);"] + ["FIELD(pbf_selftest_info, %s);" % f for f in
                                                  ("struct_size", "available", "name", "device_name", "uuid", "world", "origin")]
    missing = [w for w in want_cs if w not in cs] + [w for w in want_dump if w not in dump]
    if missing:
        report.fail("generator self-test: a new struct and function did not reach the bindings: %s" % "; ".join(missing))
    else:
        report.ok("generator self-test: a new struct (char[32], char[128], uint8_t[16], a nested handle, "
                  "float[3]) and a function filling it reach Native.cs and layout_dump.c")


def main():
    print("== C# mirror of %s" % os.path.relpath(P.HEADER, P.ROOT))
    report = P.Report("csharp mirror")
    check(report)
    selftest(report)
    return report.close()


if __name__ == "__main__":
    sys.exit(main())
