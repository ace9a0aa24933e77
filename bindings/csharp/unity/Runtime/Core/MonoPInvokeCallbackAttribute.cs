using System;

namespace Pbf.Interop
{
    /// <summary>
    /// Marks a static method that native code calls through a function pointer. Unity's IL2CPP
    /// (and Xamarin's full AOT) match this attribute by its name and generate a native entry point
    /// for the method, so reverse P/Invoke works without JIT. The bindings define their own copy so
    /// they compile without UnityEngine; on .NET and Mono JIT it does nothing.
    /// </summary>
    [AttributeUsage(AttributeTargets.Method, AllowMultiple = false, Inherited = false)]
    public sealed class MonoPInvokeCallbackAttribute : Attribute
    {
        public MonoPInvokeCallbackAttribute(Type delegateType) { DelegateType = delegateType; }

        /// <summary>The delegate type the native side calls the method as.</summary>
        public Type DelegateType { get; private set; }
    }
}
