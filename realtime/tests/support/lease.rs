//! A renderer for each test thread, lent from a pool: shared by the realtime tests
//! (`support/mod.rs`) and the workspace's parity tests (`tests/tests/parity_support`, which
//! include this file by path).
//!
//! Why not one renderer per test binary: on lavapipe a pipeline's machine code is compiled
//! (by LLVM) on the renderer's queue thread when a frame first draws with it, and a
//! renderer's renders are serialised, so with one renderer a test binary kept one core busy
//! however many test threads it ran. With one renderer per running test the compiles of
//! two tests overlap (`realtime/tests/texture` from a cold Mesa shader cache: 159 s with
//! one, 132 s with one per test). A test thread takes an idle renderer, or makes one, and
//! gives it back when it ends, so a binary holds no more renderers than it runs tests at
//! once and later tests find the pipelines earlier ones built.

use std::sync::Mutex;

use realtime::Renderer;

/// Renderers no running test holds.
static IDLE: Mutex<Vec<&'static Renderer>> = Mutex::new(Vec::new());

/// A renderer held by one test thread until it ends.
struct Lease(&'static Renderer);

impl Drop for Lease {
    fn drop(&mut self) {
        IDLE.lock().unwrap_or_else(|p| p.into_inner()).push(self.0);
    }
}

/// This test thread's renderer. No adapter is a test failure whose message says what to
/// install.
pub fn renderer() -> &'static Renderer {
    thread_local! {
        static LEASE: Lease = Lease(IDLE.lock().unwrap_or_else(|p| p.into_inner()).pop().unwrap_or_else(|| {
            Box::leak(Box::new(Renderer::new().unwrap_or_else(|e| {
                panic!("these tests need a GPU adapter: {e} (run ./scripts/setup.sh)")
            })))
        }));
    }
    LEASE.with(|l| l.0)
}
