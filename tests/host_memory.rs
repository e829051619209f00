//! No leak per frame: 200 frames of an animated render (validation on, the
//! simulation stepping with a ball rolling through, occlusion culling
//! against each last frame's depth, every frame read back,
//! written as PNG and added to the GIF) keep host memory flat after
//! warm-up, measured two ways: the process's resident set (RSS), and
//! malloc's bytes in use, which sees a small leak at once where the RSS
//! hides it in the heap's free room.
//! Leaked Vulkan objects are validation's to find (at vkDestroyDevice);
//! this finds host memory kept per frame by meadow, the driver or the layer.

use crate::common;

use meadow::commands::render::render_to_dir_observed;
use meadow::scene::Scene;

/// Resident set size of this process, from /proc/self/status (bytes).
fn rss_bytes() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status
        .lines()
        .find(|l| l.starts_with("VmRSS:"))
        .expect("VmRSS in /proc/self/status");
    let kib: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    kib * 1024
}

/// glibc's `struct mallinfo2` (malloc.h, glibc 2.33+): ten size_t fields.
#[repr(C)]
#[derive(Default)]
struct MallInfo2 {
    arena: usize,
    ordblks: usize,
    smblks: usize,
    hblks: usize,
    hblkhd: usize,
    usmblks: usize,
    fsmblks: usize,
    uordblks: usize,
    fordblks: usize,
    keepcost: usize,
}

extern "C" {
    fn mallinfo2() -> MallInfo2;
}

/// Bytes malloc has handed out and not had back, in every arena and in
/// mmapped chunks: unlike the RSS, a leak shows here at once, even while
/// the heap still has free room to serve it from.
fn malloc_in_use() -> u64 {
    // SAFETY: mallinfo2 only reads malloc's statistics; it takes no
    // arguments and returns the struct by value.
    let info = unsafe { mallinfo2() };
    (info.uordblks + info.hblkhd) as u64
}

const FRAMES: u32 = 200;
/// Frames before the resident set settles: the first frames grow it in
/// one-off steps (glibc raising its mmap threshold to the frame's size and
/// serving later frames from a heap that then stays, the report's
/// per-frame records doubling), measured at about 1.3 MiB by frame 25.
const WARM_UP: usize = 50;
/// Each level is the least of this many consecutive samples. A leak raises
/// even the least; a transient does not: lavapipe now and then holds about
/// 3.7 MiB more at one frame's end, gone by the next frame (about one run
/// in four, at a frame that varies, with the layer off too), and a
/// single-sample peak made that look like growth.
const WINDOW: usize = 10;
/// The resident set may step up once or twice after warm-up (glibc growing
/// a heap or arena, seen up to 1.4 MiB, at a frame that varies run to run);
/// one 320x180 frame (225 KiB of RGBA) kept per frame would add 33 MiB.
const MAX_RSS_GROWTH: u64 = 4 << 20;
/// malloc's bytes in use grow only by the report's per-frame records
/// (names, timings: 60-160 KiB measured over 150 frames); 3.5 KiB kept per
/// frame would pass this.
const MAX_IN_USE_GROWTH: u64 = 512 << 10;

/// Host memory held across the warm-up's last frames and across the run's
/// last frames: what stays, not what passes.
fn settled(samples: &[u64]) -> (u64, u64) {
    let least = |w: &[u64]| *w.iter().min().unwrap();
    (
        least(&samples[WARM_UP - WINDOW..WARM_UP]),
        least(&samples[samples.len() - WINDOW..]),
    )
}

fn kib(samples: &[u64]) -> Vec<u64> {
    samples.iter().map(|b| b / 1024).collect()
}

#[test]
fn two_hundred_frames_do_not_grow_host_memory_after_warm_up() {
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.light.shadow_map = 1024;
    // A coarser wind grid than the scene's, for time: the frames are what
    // is measured here, not the solver.
    scene.wind.cells = [24, 10, 24];
    // A ball rolling round the bunches, so that the colliders' kernels
    // (binning, the touching blades' indirect step) run every step too.
    scene.colliders.push(meadow::model::contact::Collider {
        radius: 0.15,
        path: vec![
            glam::Vec3::new(-0.5, 0.15, -0.25),
            glam::Vec3::new(0.5, 0.15, -0.25),
            glam::Vec3::new(0.5, 0.15, 0.25),
        ],
        path_speed: 0.8,
        closed: true,
        roll: true,
        ..Default::default()
    });
    // Occlusion culling on (off by default): the depth pyramid is built and
    // read every frame too.
    scene.cull.occlusion = true;
    let request = common::strict_request(scene, 320, 180, FRAMES, 30.0);
    let dir = common::binary::temp_out("rss");
    let mut rss = Vec::new();
    let mut in_use = Vec::new();
    // Once per frame written (the observer also hears of the breaks
    // between a frame's submissions, where a stop may come).
    let report = render_to_dir_observed(&request, &dir, &mut |progress| {
        if progress.written as usize == rss.len() + 1 {
            rss.push(rss_bytes());
            in_use.push(malloc_in_use());
        }
        true
    })
    .expect("render");
    assert_eq!(report.frames.len(), FRAMES as usize);
    assert_eq!(report.validation.errors, 0);
    assert_eq!(rss.len(), FRAMES as usize);
    let mib = |b: u64| b as f64 / 1048576.0;
    let (rss_warm, rss_end) = settled(&rss);
    let (held_warm, held_end) = settled(&in_use);
    eprintln!(
        "RSS (least of {WINDOW} frames) at frame {WARM_UP}: {:.1} MiB; at frame {FRAMES}: {:.1} MiB; \
         highest after warm-up {:.1} MiB",
        mib(rss_warm),
        mib(rss_end),
        mib(*rss[WARM_UP..].iter().max().unwrap())
    );
    eprintln!(
        "malloc in use (least of {WINDOW} frames) at frame {WARM_UP}: {:.1} MiB; at frame {FRAMES}: \
         {:.1} MiB ({:+} KiB); highest after warm-up {:.1} MiB",
        mib(held_warm),
        mib(held_end),
        (held_end as i64 - held_warm as i64) / 1024,
        mib(*in_use[WARM_UP..].iter().max().unwrap())
    );
    assert!(
        rss_end <= rss_warm + MAX_RSS_GROWTH,
        "the RSS grew by {} KiB over frames {WARM_UP}..{FRAMES}: {:?}",
        (rss_end - rss_warm) / 1024,
        kib(&rss)
    );
    assert!(
        held_end <= held_warm + MAX_IN_USE_GROWTH,
        "malloc's bytes in use grew by {} KiB over frames {WARM_UP}..{FRAMES}: {:?}",
        (held_end - held_warm) / 1024,
        kib(&in_use)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
