using System;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>
    /// A libpbf call failed. <see cref="Code"/> is the native pbf_result and
    /// <see cref="Exception.Message"/> the text of pbf_last_error_message() read right after the
    /// failing call, on the same thread (for example
    /// "PBF_ERROR_INVALID_HANDLE: pbf_world_step: world {0, 2} is not a live world ...").
    /// A failed call changes nothing in the world.
    /// </summary>
    public class PbfException : Exception
    {
        public PbfException(Result code, string nativeMessage)
            : base(string.IsNullOrEmpty(nativeMessage) ? code.ToString() : nativeMessage)
        {
            Code = code;
            NativeMessage = nativeMessage ?? string.Empty;
        }

        /// <summary>The native result code.</summary>
        public Result Code { get; private set; }

        /// <summary>pbf_last_error_message() of the failed call ("" when the library gave none).</summary>
        public string NativeMessage { get; private set; }

        /// <summary>Throws a PbfException for any result other than PBF_OK. Call it directly
        /// after the native call, on the same thread, so the thread-local message still belongs
        /// to that call.</summary>
        public static void Check(pbf_result result)
        {
            if (result != pbf_result.PBF_OK) throw FromResult(result);
        }

        internal static PbfException FromResult(pbf_result result)
        {
            return new PbfException((Result)result, Native.LastErrorMessage());
        }
    }
}
