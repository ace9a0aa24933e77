using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using NUnit.Framework;

namespace Pbf.Tests
{
    [TestFixture]
    public class LogTests
    {
        readonly List<KeyValuePair<LogLevel, string>> _messages = new List<KeyValuePair<LogLevel, string>>();
        readonly List<int> _threads = new List<int>();

        void Collect(LogLevel level, string message)
        {
            lock (_messages)
            {
                _messages.Add(new KeyValuePair<LogLevel, string>(level, message));
                _threads.Add(Thread.CurrentThread.ManagedThreadId);
            }
        }

        [SetUp]
        public void SetUp()
        {
            lock (_messages) { _messages.Clear(); _threads.Clear(); }
        }

        [TearDown]
        public void TearDown() { Library.SetLogHandler(null); }

        [Test]
        public void HandlerReceivesEventsAndEveryError()
        {
            Library.SetLogHandler(Collect);
            using (var world = Scene.CpuWorld())
            {
                lock (_messages)
                {
                    Assert.IsTrue(_messages.Exists(m => m.Key == LogLevel.Info && m.Value.Contains("world created on CPU")),
                        "creation is logged");
                    _messages.Clear();
                    _threads.Clear();
                }
                var e = Assert.Throws<PbfException>(() => world.Step(-1f));
                lock (_messages)
                {
                    Assert.AreEqual(1, _messages.Count);
                    Assert.AreEqual(LogLevel.Error, _messages[0].Key);
                    Assert.AreEqual(e.Message, _messages[0].Value, "the logged text is the exception's message");
                }

                // From another thread: the handler runs on the calling thread.
                int other = -1;
                var t = new Thread(() =>
                {
                    other = Thread.CurrentThread.ManagedThreadId;
                    try { world.SetGravity(new Vector3(float.NaN, 0, 0)); } catch (PbfException) { }
                });
                t.Start();
                t.Join();
                lock (_messages)
                {
                    Assert.AreEqual(2, _messages.Count);
                    Assert.AreEqual(other, _threads[1]);
                    StringAssert.Contains("pbf_world_set_gravity", _messages[1].Value);
                }

                Library.SetLogHandler(null);
                Assert.Throws<PbfException>(() => world.Step(0f));
                lock (_messages) Assert.AreEqual(2, _messages.Count, "removed handler gets nothing");
            }
        }

        [Test]
        public void ReplacingTheHandlerRoutesToTheNewOne()
        {
            int first = 0, second = 0;
            Library.SetLogHandler((l, m) => ++first);
            using (var world = Scene.CpuWorld())
            {
                Assert.Throws<PbfException>(() => world.Step(0f));
                Library.SetLogHandler((l, m) => ++second);
                Assert.Throws<PbfException>(() => world.Step(0f));
                Assert.Throws<PbfException>(() => world.Step(0f));
            }
            Assert.AreEqual(2, first, "world creation and one error");
            Assert.AreEqual(2, second);
        }

        [Test]
        public void AThrowingHandlerNeverReachesNativeCode()
        {
            int calls = 0;
            Library.SetLogHandler((l, m) => { ++calls; throw new InvalidOperationException("handler bug"); });
            using (var world = Scene.CpuWorld())
            {
                var e = Assert.Throws<PbfException>(() => world.Step(float.NaN));
                Assert.AreEqual(Result.InvalidArgument, e.Code);
                world.EmitBlock(new Vector3(-0.1f, 0, -0.1f), new Vector3(0.1f, 0.1f, 0.1f));
                world.Step(Scene.Dt);
            }
            Assert.AreEqual(2, calls);
        }
    }
}
