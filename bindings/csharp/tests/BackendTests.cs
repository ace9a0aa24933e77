using System;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>
    /// Backend selection: Library.GetBackendInfo and the world's backend and CUDA-not-taken reason.
    /// The CPU backend is always there. CUDA is described either way (available, or a status and a
    /// message that says why not), so the tests hold on a machine with a GPU as on one without;
    /// where they need CUDA to be missing (this machine, and CI) they say so with Assert.Ignore.
    /// </summary>
    [TestFixture]
    public class BackendTests
    {
        const string NotTaken = "CUDA not taken: ";

        [Test]
        public void CpuIsAlwaysAvailable()
        {
            BackendInfo cpu = Library.GetBackendInfo(Backend.Cpu);
            Assert.AreEqual(Backend.Cpu, cpu.Backend);
            Assert.AreEqual(BackendStatus.Available, cpu.Status);
            Assert.IsTrue(cpu.IsAvailable);
            Assert.AreEqual(-1, cpu.CudaDevice);
            StringAssert.StartsWith("CPU (", cpu.DeviceName);
            StringAssert.EndsWith(" threads)", cpu.DeviceName);
            Assert.IsNotEmpty(cpu.Message);
            // The device is ignored for the CPU: any ordinal, even a negative one.
            Assert.AreEqual(cpu.DeviceName, Library.GetBackendInfo(Backend.Cpu, -3).DeviceName);
            // The raw struct as the library filled it.
            Assert.AreEqual(pbf_backend.PBF_BACKEND_CPU, cpu.ToNative().backend);
            Assert.AreEqual(Native.SizeOf<pbf_backend_info>(), cpu.ToNative().struct_size);
        }

        [Test]
        public void CudaIsDescribedAndAutoFollowsIt()
        {
            BackendInfo cuda = Library.GetBackendInfo(Backend.Cuda, 0);
            BackendInfo auto = Library.GetBackendInfo();  // Auto on device 0
            Assert.AreEqual(Backend.Cuda, cuda.Backend);
            Assert.IsTrue(Enum.IsDefined(typeof(BackendStatus), cuda.Status), "status " + (int)cuda.Status);
            Assert.IsNotEmpty(cuda.Message);
            // Driver facts are the same whichever backend is asked about.
            Assert.AreEqual(cuda.DriverVersion, auto.DriverVersion);
            Assert.AreEqual(cuda.RequiredDriverVersion, auto.RequiredDriverVersion);
            Assert.AreEqual(cuda.DeviceCount, auto.DeviceCount);
            if (cuda.IsAvailable)
            {
                Assert.AreEqual(Backend.Cuda, auto.Backend);
                Assert.AreEqual(0, cuda.CudaDevice);
                Assert.Greater(cuda.DeviceCount, 0);
                Assert.GreaterOrEqual(cuda.DriverVersion, cuda.RequiredDriverVersion);
                Assert.IsNotEmpty(cuda.DeviceName);
                return;
            }
            Assert.AreEqual(Backend.Cpu, auto.Backend);
            Assert.AreEqual(BackendStatus.Available, auto.Status, "Auto falls back to the CPU, which is available");
            Assert.AreEqual(NotTaken + cuda.Message, auto.Message);
            StringAssert.StartsWith("CPU (", auto.DeviceName);
            switch (cuda.Status)
            {
                case BackendStatus.NotBuilt:
                    Assert.AreEqual(0, cuda.DriverVersion);
                    Assert.AreEqual(0, cuda.RequiredDriverVersion);
                    Assert.AreEqual(0, cuda.DeviceCount);
                    StringAssert.Contains("built without CUDA", cuda.Message);
                    break;
                case BackendStatus.NoDriver:
                    Assert.AreEqual(0, cuda.DriverVersion);
                    Assert.AreEqual(0, cuda.DeviceCount);
                    Assert.Greater(cuda.RequiredDriverVersion, 0);
                    break;
                case BackendStatus.DriverTooOld:
                    Assert.Less(cuda.DriverVersion, cuda.RequiredDriverVersion);
                    break;
                case BackendStatus.NoDevice:
                    Assert.LessOrEqual(cuda.DeviceCount, 0);
                    break;
            }
        }

        [Test]
        public void CpuOnlyBuildSaysSo()
        {
            if ((Library.GetInteropSupport() & InteropSupport.Cuda) != 0)
                Assert.Ignore("this libpbf was built with CUDA; the test is for the CPU-only build");
            BackendInfo cuda = Library.GetBackendInfo(Backend.Cuda);
            Assert.AreEqual(BackendStatus.NotBuilt, cuda.Status);
            Assert.AreEqual("this libpbf was built without CUDA (PBF_WITH_CUDA=OFF)", cuda.Message);
            Assert.AreEqual("", cuda.DeviceName);
            Assert.AreEqual(NotTaken + "this libpbf was built without CUDA (PBF_WITH_CUDA=OFF)", Library.GetBackendInfo().Message);
            Assert.AreEqual("Cuda (NotBuilt): this libpbf was built without CUDA (PBF_WITH_CUDA=OFF)", cuda.ToString());
        }

        [Test]
        public void ArgumentsAreChecked()
        {
            Scene.ExpectError(Result.InvalidArgument, () => Library.GetBackendInfo((Backend)3), "pbf_get_backend_info", "backend must be");
            Scene.ExpectError(Result.InvalidArgument, () => Library.GetBackendInfo((Backend)(-1)), "backend must be");
            Scene.ExpectError(Result.InvalidArgument, () => Library.GetBackendInfo(Backend.Cuda, -1), "cuda_device must be >= 0");
            Scene.ExpectError(Result.InvalidArgument, () => Library.GetBackendInfo(Backend.Auto, -1), "cuda_device must be >= 0");

            // The raw call: a NULL or short struct.
            Assert.AreEqual(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_get_backend_info(pbf_backend.PBF_BACKEND_CPU, 0, IntPtr.Zero));
            var small = new pbf_backend_info { struct_size = Native.SizeOf<pbf_backend_info>() - 4 };
            Assert.AreEqual(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_get_backend_info(pbf_backend.PBF_BACKEND_CPU, 0, ref small));
            StringAssert.Contains("struct_size", Native.LastErrorMessage());
        }

        [Test]
        public void NoCudaDeviceOfAHighOrdinal()
        {
            BackendInfo cuda = Library.GetBackendInfo(Backend.Cuda, 4096);
            Assert.AreNotEqual(BackendStatus.Available, cuda.Status, "no machine has 4097 CUDA devices");
            Assert.IsNotEmpty(cuda.Message);
            BackendInfo auto = Library.GetBackendInfo(Backend.Auto, 4096);
            Assert.AreEqual(Backend.Cpu, auto.Backend);
            Assert.AreEqual(NotTaken + cuda.Message, auto.Message);
            if (cuda.DeviceCount > 0)
            {
                Assert.AreEqual(BackendStatus.NoDevice, cuda.Status);
                StringAssert.Contains("4096", cuda.Message);
            }
        }

        [Test]
        public void WorldKeepsItsBackendAndWhyCudaWasNotTaken()
        {
            using (World cpu = Scene.CpuWorld(256))
            {
                Assert.AreEqual(Backend.Cpu, cpu.Backend);
                Assert.AreEqual(cpu.Info.Backend, cpu.Backend);
                Assert.AreEqual(Backend.Cpu, cpu.RequestedBackend);
                Assert.AreEqual("CUDA not taken: the world asked for the CPU backend", cpu.CudaNotTakenReason);
            }

            BackendInfo expected = Library.GetBackendInfo(Backend.Auto, 0);
            using (World auto = World.Create(new WorldDesc { Backend = Backend.Auto, MaxParticles = 256 }))
            {
                Assert.AreEqual(Backend.Auto, auto.RequestedBackend);
                Assert.AreEqual(0, auto.CudaDevice);
                Assert.AreEqual(expected.Backend, auto.Backend, "Auto picks what GetBackendInfo(Auto) says");
                Assert.AreEqual(auto.Info.Backend, auto.Backend);
                Assert.AreEqual(expected.DeviceName, auto.Info.DeviceName);
                if (auto.Backend == Backend.Cuda)
                {
                    Assert.AreEqual("", auto.CudaNotTakenReason);
                }
                else
                {
                    StringAssert.StartsWith(NotTaken, auto.CudaNotTakenReason);
                    Assert.AreEqual(expected.Message, auto.CudaNotTakenReason);
                }
            }

            // An ordinal no machine has: Auto runs on the CPU and says why.
            using (World far = World.Create(new WorldDesc { Backend = Backend.Auto, CudaDevice = 4096, MaxParticles = 256 }))
            {
                Assert.AreEqual(Backend.Cpu, far.Backend);
                Assert.AreEqual(4096, far.CudaDevice);
                Assert.AreEqual(NotTaken + Library.GetBackendInfo(Backend.Cuda, 4096).Message, far.CudaNotTakenReason);
            }
        }

        [Test]
        public void DisposedWorldRefusesBackendQueries()
        {
            World w = Scene.CpuWorld(64);
            w.Dispose();
            Assert.Throws<ObjectDisposedException>(() => { var b = w.Backend; });
            Assert.Throws<ObjectDisposedException>(() => { var r = w.CudaNotTakenReason; });
        }

        [Test]
        public void DriverVersionsReadAsMajorMinor()
        {
            Assert.AreEqual("13.0", BackendInfo.VersionString(13000));
            Assert.AreEqual("12.4", BackendInfo.VersionString(12040));
            Assert.AreEqual("0.0", BackendInfo.VersionString(0));
        }
    }
}
