using System;
using System.Runtime.InteropServices;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>Receives libpbf's log messages (every error, and events such as "world created").</summary>
    /// <remarks>Runs on whichever thread made the libpbf call that logged, while libpbf holds its
    /// process-wide log lock: keep it short, and do not call libpbf from it (a failing call would
    /// log again and wait on that lock forever).</remarks>
    public delegate void LogHandler(LogLevel level, string message);

    /// <summary>Process-wide parts of libpbf: versions, backends and logging.</summary>
    public static partial class Library
    {
        /// <summary>PBF_VERSION of the header these bindings mirror.</summary>
        public const uint HeaderVersion = Native.PBF_VERSION;

        /// <summary>pbf_get_version(): the version the loaded native library was built as.</summary>
        public static uint Version { get { return Native.pbf_get_version(); } }

        /// <summary>True when the loaded library's major version equals the bindings' (the only
        /// requirement of the ABI; pbf_world_create refuses otherwise).</summary>
        public static bool IsCompatible
        {
            get { return Native.PBF_VERSION_GET_MAJOR(Version) == Native.PBF_VERSION_GET_MAJOR(HeaderVersion); }
        }

        /// <summary>"major.minor.patch" of a packed PBF_VERSION value.</summary>
        public static string VersionString(uint version)
        {
            return Native.PBF_VERSION_GET_MAJOR(version) + "." + Native.PBF_VERSION_GET_MINOR(version) + "." +
                   Native.PBF_VERSION_GET_PATCH(version);
        }

        /// <summary>
        /// pbf_get_backend_info(): whether backend can run on this machine (on CUDA device
        /// cudaDevice; ignored for the CPU), and if not, why. For <see cref="Backend.Auto"/>, the
        /// backend a world created with Auto on that device gets, and when that is the CPU, why
        /// CUDA was not taken. Unavailable is an answer, not an error: it throws only for bad
        /// arguments (<see cref="Result.InvalidArgument"/>: a backend outside the enum, a negative
        /// cudaDevice for Auto or Cuda). The first call that looks at a CUDA device opens the
        /// NVIDIA driver and loads the kernels (tens to hundreds of milliseconds); later calls and
        /// world creations reuse them, but a failure is tried again at each call.
        /// </summary>
        public static BackendInfo GetBackendInfo(Backend backend = Backend.Auto, int cudaDevice = 0)
        {
            var info = new pbf_backend_info { struct_size = Native.SizeOf<pbf_backend_info>() };
            PbfException.Check(Native.pbf_get_backend_info((pbf_backend)backend, cudaDevice, ref info));
            return new BackendInfo(info);
        }

        /// <summary>pbf_result_string(): the static name of a result, e.g. "PBF_ERROR_INVALID_HANDLE".</summary>
        public static string ResultString(Result result) { return Native.ResultString((pbf_result)result); }

        // ---- logging ---------------------------------------------------------------------------
        static readonly object s_logLock = new object();
        // One static thunk for the process: the delegate object and its function pointer live as
        // long as this class, so native code never calls a collected delegate.
        static pbf_log_fn s_thunk;
        static IntPtr s_thunkPointer;
        static GCHandle s_handler;  // the current LogHandler, passed to native code as user_data
        static bool s_unloadHooked;

        /// <summary>Installs handler as libpbf's process-wide log callback (null removes it).
        /// Replacing or removing a handler waits for a call in progress on another thread.</summary>
        public static void SetLogHandler(LogHandler handler)
        {
            lock (s_logLock)
            {
                GCHandle previous = s_handler;
                if (handler == null)
                {
                    Native.pbf_set_log_callback(IntPtr.Zero, IntPtr.Zero);
                    s_handler = default(GCHandle);
                }
                else
                {
                    if (s_thunk == null)
                    {
                        s_thunk = OnNativeLog;
                        s_thunkPointer = Marshal.GetFunctionPointerForDelegate(s_thunk);
                    }
                    if (!s_unloadHooked)
                    {
                        // The native library outlives an app domain (Unity's editor reloads its
                        // domain on every script change): unhook before our delegate goes away.
                        AppDomain.CurrentDomain.DomainUnload += OnUnload;
                        AppDomain.CurrentDomain.ProcessExit += OnUnload;
                        s_unloadHooked = true;
                    }
                    GCHandle current = GCHandle.Alloc(handler);
                    Native.pbf_set_log_callback(s_thunkPointer, GCHandle.ToIntPtr(current));
                    s_handler = current;
                }
                // pbf_set_log_callback takes the lock that every callback runs under, so once it
                // has returned no call is still using the previous handle.
                if (previous.IsAllocated) previous.Free();
            }
        }

        static void OnUnload(object sender, EventArgs e)
        {
            try { SetLogHandler(null); }
            catch (Exception) { /* the library may never have been loaded */ }
        }

        [MonoPInvokeCallback(typeof(pbf_log_fn))]
        static void OnNativeLog(pbf_log_level level, IntPtr message, IntPtr userData)
        {
            // Never let an exception unwind into native code.
            try
            {
                if (userData == IntPtr.Zero) return;
                var handler = GCHandle.FromIntPtr(userData).Target as LogHandler;
                if (handler != null) handler((LogLevel)level, Native.Utf8ToString(message));
            }
            catch (Exception)
            {
            }
        }
    }
}
