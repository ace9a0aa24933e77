using System;
using System.Collections.Generic;
using System.Globalization;
using System.IO;
using System.Linq;
using System.Reflection;
using System.Runtime.InteropServices;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>
    /// The C# mirror against the header as it is now: tools/layout_dump.c, compiled by
    /// run_tests.sh with the current include/pbf_c_api.h, writes the sizes, offsets and enum values
    /// that the C compiler sees; these tests compare each with Marshal.SizeOf/OffsetOf and the C#
    /// enums. The file comes from $PBF_LAYOUT_FILE, else layout_expected.txt beside this assembly.
    /// </summary>
    [TestFixture]
    public class LayoutTests
    {
        static readonly string[] s_lines = LoadDump();

        static string[] LoadDump()
        {
            string path = Environment.GetEnvironmentVariable("PBF_LAYOUT_FILE");
            if (string.IsNullOrEmpty(path))
                path = Path.Combine(Path.GetDirectoryName(typeof(LayoutTests).Assembly.Location), "layout_expected.txt");
            return File.Exists(path) ? File.ReadAllLines(path) : null;
        }

        static IEnumerable<string[]> Facts(string kind)
        {
            if (s_lines == null)
                Assert.Fail("layout_expected.txt not found: run bindings/csharp/run_tests.sh, which builds and runs tools/layout_dump.c");
            return s_lines.Select(l => l.Split(' ')).Where(f => f[0] == kind);
        }

        static Type Mirror(string cName)
        {
            Type t = typeof(Native).Assembly.GetType("Pbf.Interop." + cName);
            Assert.IsNotNull(t, "no C# mirror Pbf.Interop." + cName);
            return t;
        }

        static int FieldSize(Type t)
        {
            return Marshal.SizeOf(t.IsEnum ? Enum.GetUnderlyingType(t) : t);
        }

        [Test]
        public void StructSizesMatchHeader()
        {
            int checkedCount = 0;
            foreach (var f in Facts("struct"))
            {
                Type t = Mirror(f[1]);
                Assert.IsTrue(t.IsValueType && t.IsLayoutSequential, f[1] + " must be a sequential struct");
                Assert.AreEqual(int.Parse(f[2]), Marshal.SizeOf(t), "sizeof(" + f[1] + ")");
                ++checkedCount;
            }
            Assert.Greater(checkedCount, 0, "structs in the dump");
        }

        [Test]
        public void FieldOffsetsAndSizesMatchHeader()
        {
            var seen = new Dictionary<string, HashSet<string>>();
            foreach (var f in Facts("field"))
            {
                Type t = Mirror(f[1]);
                FieldInfo fi = t.GetField(f[2], BindingFlags.Public | BindingFlags.Instance);
                Assert.IsNotNull(fi, f[1] + "." + f[2] + " is missing in C#");
                Assert.AreEqual(int.Parse(f[3]), (int)Marshal.OffsetOf(t, f[2]), "offsetof(" + f[1] + ", " + f[2] + ")");
                Assert.AreEqual(int.Parse(f[4]), FieldSize(fi.FieldType), "sizeof(" + f[1] + "." + f[2] + ")");
                if (!seen.ContainsKey(f[1])) seen[f[1]] = new HashSet<string>();
                seen[f[1]].Add(f[2]);
            }
            // And no C# field that the header lacks.
            foreach (var kv in seen)
                foreach (FieldInfo fi in Mirror(kv.Key).GetFields(BindingFlags.Public | BindingFlags.NonPublic | BindingFlags.Instance))
                    Assert.IsTrue(kv.Value.Contains(fi.Name), kv.Key + "." + fi.Name + " is not in the header");
        }

        [Test]
        public void EveryMirroredStructIsInTheHeaderDump()
        {
            var dumped = new HashSet<string>(Facts("struct").Select(f => f[1]));
            var mirrors = typeof(Native).Assembly.GetTypes()
                .Where(t => t.Namespace == "Pbf.Interop" && t.IsValueType && !t.IsEnum && t.Name.StartsWith("pbf_"));
            foreach (Type t in mirrors) Assert.IsTrue(dumped.Contains(t.Name), t.Name + " is not a struct of the header");
        }

        [Test]
        public void EnumValuesAndSizesMatchHeader()
        {
            var members = new Dictionary<string, HashSet<string>>();
            foreach (var f in Facts("enum"))
            {
                Type t = Mirror(f[1]);
                Assert.IsTrue(t.IsEnum);
                Assert.IsTrue(Enum.IsDefined(t, f[2]), f[1] + "." + f[2] + " is missing in C#");
                long value = Convert.ToInt64(Enum.Parse(t, f[2]), CultureInfo.InvariantCulture);
                Assert.AreEqual(long.Parse(f[3], CultureInfo.InvariantCulture), value, f[2]);
                if (!members.ContainsKey(f[1])) members[f[1]] = new HashSet<string>();
                members[f[1]].Add(f[2]);
            }
            Assert.Greater(members.Count, 0, "enum types in the dump");
            // Every raw enum of the bindings is in the dump.
            foreach (Type t in typeof(Native).Assembly.GetTypes().Where(t => t.Namespace == "Pbf.Interop" && t.IsEnum))
                Assert.IsTrue(members.ContainsKey(t.Name), t.Name + " is not an enum of the header");
            foreach (var kv in members)
                foreach (string name in Enum.GetNames(Mirror(kv.Key)))
                    Assert.IsTrue(kv.Value.Contains(name), kv.Key + "." + name + " is not in the header");
            foreach (var f in Facts("enumsize"))
                Assert.AreEqual(int.Parse(f[2]), FieldSize(Mirror(f[1])), "sizeof(" + f[1] + ")");
        }

        [Test]
        public void VersionConstantsMatchHeader()
        {
            int n = 0;
            foreach (var f in Facts("const"))
            {
                FieldInfo fi = typeof(Native).GetField(f[1], BindingFlags.Public | BindingFlags.Static);
                Assert.IsNotNull(fi, "Native." + f[1]);
                Assert.IsTrue(fi.IsLiteral, "Native." + f[1] + " must be a const");
                // uint for the header's unsigned macros, int for PBF_RENDER_EVENT_ALL_WORLDS.
                Assert.AreEqual(long.Parse(f[2], CultureInfo.InvariantCulture),
                                Convert.ToInt64(fi.GetValue(null), CultureInfo.InvariantCulture), f[1]);
                ++n;
            }
            Assert.GreaterOrEqual(n, 4, "PBF_VERSION_MAJOR, _MINOR, _PATCH and PBF_VERSION");
            Assert.AreEqual(Native.PBF_VERSION, Native.PBF_MAKE_VERSION(Native.PBF_VERSION_MAJOR, Native.PBF_VERSION_MINOR, Native.PBF_VERSION_PATCH));
        }

        [Test]
        public void FriendlyEnumsHaveTheRawValues()
        {
            var pairs = new[]
            {
                Tuple.Create(typeof(pbf_result), typeof(Result)),
                Tuple.Create(typeof(pbf_log_level), typeof(LogLevel)),
                Tuple.Create(typeof(pbf_backend), typeof(Backend)),
                Tuple.Create(typeof(pbf_backend_status), typeof(BackendStatus)),
                Tuple.Create(typeof(pbf_emitter_type), typeof(EmitterType)),
                Tuple.Create(typeof(pbf_collider_shape), typeof(ColliderShape)),
                Tuple.Create(typeof(pbf_collider_motion), typeof(ColliderMotion)),
                Tuple.Create(typeof(pbf_memory_kind), typeof(MemoryKind)),
                Tuple.Create(typeof(pbf_buffer), typeof(BufferSource)),
                Tuple.Create(typeof(pbf_copy_mode), typeof(CopyMode)),
            };
            foreach (var p in pairs)
            {
                var raw = Enum.GetValues(p.Item1).Cast<object>().Select(v => Convert.ToInt32(v)).Where(v => v != 0x7FFFFFFF).OrderBy(v => v).ToArray();
                var friendly = Enum.GetValues(p.Item2).Cast<object>().Select(v => Convert.ToInt32(v)).OrderBy(v => v).ToArray();
                CollectionAssert.AreEqual(raw, friendly, p.Item2.Name);
            }
        }
    }
}
