// The hand-written part of Native (Native.cs is generated from include/pbf_c_api.h): the library's
// name, the header's function-like macros, and helpers for the generated declarations.
using System;
using System.Runtime.InteropServices;

namespace Pbf.Interop
{
    public static partial class Native
    {
        /// <summary>The native library's name: libpbf.so / libpbf.dylib / pbf.dll. Where libpbf is
        /// linked statically into the player (iOS, WebGL; or any build defining PBF_STATIC_LINK)
        /// it is "__Internal".</summary>
#if PBF_STATIC_LINK || ((UNITY_IOS || UNITY_TVOS || UNITY_WEBGL) && !UNITY_EDITOR)
        public const string Library = "__Internal";
#else
        public const string Library = "pbf";
#endif

        // The header's version macros: major in bits 22..31, minor in 12..21, patch in 0..11.
        public static uint PBF_MAKE_VERSION(uint major, uint minor, uint patch) { return (major << 22) | (minor << 12) | patch; }
        public static uint PBF_VERSION_GET_MAJOR(uint v) { return v >> 22; }
        public static uint PBF_VERSION_GET_MINOR(uint v) { return (v >> 12) & 0x3FFu; }
        public static uint PBF_VERSION_GET_PATCH(uint v) { return v & 0xFFFu; }

        /// <summary>Marshal.SizeOf(T) as the struct_size a desc carries (computed once per type).</summary>
        public static uint SizeOf<T>() where T : struct { return SizeCache<T>.Value; }

        static class SizeCache<T> where T : struct
        {
            public static readonly uint Value = (uint)Marshal.SizeOf(typeof(T));
        }

        /// <summary>Decodes a NUL-terminated UTF-8 string owned by the library ("" for NULL).</summary>
        public static string Utf8ToString(IntPtr text)
        {
            if (text == IntPtr.Zero) return string.Empty;
            int n = 0;
            while (Marshal.ReadByte(text, n) != 0) ++n;
            if (n == 0) return string.Empty;
            var bytes = new byte[n];
            Marshal.Copy(text, bytes, 0, n);
            return System.Text.Encoding.UTF8.GetString(bytes);
        }

        /// <summary>pbf_last_error_message() as a string.</summary>
        public static string LastErrorMessage() { return Utf8ToString(pbf_last_error_message()); }

        /// <summary>pbf_result_string() as a string.</summary>
        public static string ResultString(pbf_result result) { return Utf8ToString(pbf_result_string(result)); }
    }
}
