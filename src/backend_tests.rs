//! The back-end policy on a machine made up for each case: every rule, and what each back end
//! does where it applies.

use std::cell::Cell;

use penumbra_geom::Technique;

use crate::backend::*;
use crate::error::{MissingGpu, RenderError};
use crate::options::RenderOptions;
use crate::runs::Runs;

/// A machine with or without a GPU, counting what the policy looked at.
struct Fake {
    gpu: Option<GpuOffer>,
    units: usize,
    extent: f64,
    memory: Option<u64>,
    opened: Cell<usize>,
    counted: Cell<usize>,
}

impl Fake {
    fn with_gpu() -> Self {
        Fake {
            gpu: Some(GpuOffer {
                adapter: "test adapter".into(),
                max_texture_side: 8192,
                max_storage_binding: 128 << 20,
            }),
            ..Fake::without_gpu()
        }
    }

    fn without_gpu() -> Self {
        Fake {
            gpu: None,
            units: 10,
            extent: 10.0,
            memory: None,
            opened: Cell::new(0),
            counted: Cell::new(0),
        }
    }
}

impl Machine for Fake {
    fn gpu(&mut self) -> Result<GpuOffer, MissingGpu> {
        self.opened.set(self.opened.get() + 1);
        self.gpu.clone().ok_or(MissingGpu::CpuChosen)
    }

    fn blend_units(&mut self) -> usize {
        self.counted.set(self.counted.get() + 1);
        self.units
    }

    fn extent_ratio(&mut self) -> f64 {
        self.extent
    }

    fn available_memory(&mut self) -> Option<u64> {
        self.memory
    }
}

fn ask(
    technique: Technique,
    backend: Backend,
    options: RenderOptions,
    machine: &mut Fake,
) -> Result<Choice, RenderError> {
    choose(
        &Request {
            technique,
            backend,
            options: &options,
            width: 320,
            height: 240,
        },
        machine,
    )
}

fn placed(
    technique: Technique,
    backend: Backend,
    options: RenderOptions,
    machine: &mut Fake,
) -> Placement {
    ask(technique, backend, options, machine)
        .unwrap_or_else(|e| panic!("{technique} on {backend:?}: {e}"))
        .placement
}

const SMALL: RenderOptions = RenderOptions {
    samples: 16,
    jitter: false,
};

#[test]
fn techniques_run_where_they_can_and_the_back_end_chosen_is_obeyed() {
    use Placement::{Cpu, Gpu};
    for t in Technique::ALL {
        let mut gpu = Fake::with_gpu();
        let mut none = Fake::without_gpu();
        match Runs::of(t) {
            Runs::GpuOnly => {
                assert_eq!(placed(t, Backend::Auto, SMALL, &mut gpu), Gpu);
                assert_eq!(placed(t, Backend::Gpu, SMALL, &mut gpu), Gpu);
                for (backend, machine) in [(Backend::Cpu, &mut gpu), (Backend::Auto, &mut none)] {
                    let err = ask(t, backend, SMALL, machine).unwrap_err();
                    assert!(matches!(err, RenderError::NeedsGpu { .. }), "{t}: {err}");
                }
            }
            Runs::CpuOnly => {
                assert_eq!(placed(t, Backend::Auto, SMALL, &mut gpu), Cpu);
                assert_eq!(placed(t, Backend::Cpu, SMALL, &mut gpu), Cpu);
                let err = ask(t, Backend::Gpu, SMALL, &mut gpu).unwrap_err();
                assert!(matches!(err, RenderError::CpuOnly { .. }), "{t}: {err}");
                // The references never open the GPU.
                assert_eq!(gpu.opened.get(), 0, "{t}");
            }
            Runs::Either => {
                // Depth-complexity sampling stays on the CPU under Auto (its own test).
                let auto = if t == Technique::DepthComplexity {
                    Cpu
                } else {
                    Gpu
                };
                assert_eq!(placed(t, Backend::Auto, SMALL, &mut gpu), auto);
                assert_eq!(placed(t, Backend::Gpu, SMALL, &mut gpu), Gpu);
                assert_eq!(placed(t, Backend::Cpu, SMALL, &mut gpu), Cpu);
                assert_eq!(placed(t, Backend::Auto, SMALL, &mut none), Cpu);
                let err = ask(t, Backend::Gpu, SMALL, &mut none).unwrap_err();
                assert!(matches!(err, RenderError::NoGpu { .. }), "{t}: {err}");
            }
        }
    }
}

#[test]
fn depth_complexity_goes_to_the_cpu_under_auto_without_opening_the_gpu() {
    let dc = Technique::DepthComplexity;
    let many = RenderOptions {
        samples: 4096,
        jitter: false,
    };
    let jittered = RenderOptions {
        samples: 16,
        jitter: true,
    };
    for options in [SMALL, many, jittered] {
        let mut machine = Fake::with_gpu();
        let c = ask(dc, Backend::Auto, options, &mut machine).unwrap();
        assert_eq!(c.placement, Placement::Cpu);
        assert!(matches!(c.reason, Reason::CountingOnCpu), "{c:?}");
        assert_eq!(machine.opened.get(), 0);
    }
    // The GPU back end renders it on the GPU up to its samples, and refuses beyond.
    let c = ask(dc, Backend::Gpu, SMALL, &mut Fake::with_gpu()).unwrap();
    assert_eq!(c.placement, Placement::Gpu);
    for options in [many, jittered] {
        let err = ask(dc, Backend::Gpu, options, &mut Fake::with_gpu()).unwrap_err();
        assert!(matches!(err, RenderError::GpuSamples { max, .. } if max == MAX_GPU_SAMPLES));
    }
}

#[test]
fn images_beyond_the_gpus_textures_go_to_the_cpu_under_auto_and_are_refused_otherwise() {
    let wide = |technique, backend, machine: &mut Fake| {
        choose(
            &Request {
                technique,
                backend,
                options: &SMALL,
                width: 9000,
                height: 1,
            },
            machine,
        )
    };
    let c = wide(Technique::Hard, Backend::Auto, &mut Fake::with_gpu()).unwrap();
    assert_eq!(c.placement, Placement::Cpu);
    assert!(matches!(
        c.reason,
        Reason::TooLargeForGpu { max_side: 8192 }
    ));
    for (t, backend) in [
        (Technique::Hard, Backend::Gpu),
        (Technique::Pcf, Backend::Auto),
    ] {
        let err = wide(t, backend, &mut Fake::with_gpu()).unwrap_err();
        assert!(
            matches!(err, RenderError::TooLargeForGpu { width: 9000, .. }),
            "{t}: {err}"
        );
    }
}

#[test]
fn wedges_blend_with_many_blending_units_goes_to_the_cpu_under_auto() {
    let mut machine = Fake::with_gpu();
    machine.units = MAX_GPU_BLEND_UNITS + 1;
    let c = ask(Technique::WedgesBlend, Backend::Auto, SMALL, &mut machine).unwrap();
    assert_eq!(c.placement, Placement::Cpu);
    assert!(matches!(c.reason, Reason::ManyBlendUnits { .. }));
    assert_eq!(
        placed(Technique::WedgesBlend, Backend::Gpu, SMALL, &mut machine),
        Placement::Gpu
    );
    // Only wedges-blend under auto counts them (counting builds the scene's volumes).
    machine.counted.set(0);
    placed(Technique::Wedges, Backend::Auto, SMALL, &mut machine);
    assert_eq!(machine.counted.get(), 0);
    machine.units = MAX_GPU_BLEND_UNITS;
    assert_eq!(
        placed(Technique::WedgesBlend, Backend::Auto, SMALL, &mut machine),
        Placement::Gpu
    );
}

#[test]
fn an_image_the_memory_would_not_hold_is_refused_on_either_back_end() {
    // 320 x 240 pixels: 1.2 MB on the CPU, 9.8 MB on the GPU.
    let mut machine = Fake::with_gpu();
    machine.memory = Some(4_000_000);
    assert_eq!(
        placed(Technique::Hard, Backend::Cpu, SMALL, &mut machine),
        Placement::Cpu
    );
    let err = ask(Technique::Hard, Backend::Gpu, SMALL, &mut machine).unwrap_err();
    assert!(
        matches!(
            err,
            RenderError::OutOfMemory {
                needed: 9_830_400,
                available: 4_000_000,
                ..
            }
        ),
        "{err}"
    );
    machine.memory = Some(1_000_000);
    let err = ask(Technique::Reference, Backend::Auto, SMALL, &mut machine).unwrap_err();
    assert!(err.to_string().contains("too large"), "{err}");
}

#[test]
fn depth_complexity_on_the_gpu_is_charged_its_counting_buffer() {
    // 320 x 240 pixels at 256 samples: 9.8 MB of targets, and the counting pass's buffer of
    // 4 bytes of V and 288 of state and counts per pixel, 22.4 MB: 32.3 MB in all.
    let counting = penumbra_gpu::count_buffer_bytes((320, 240), 256, 128 << 20).unwrap();
    assert_eq!(counting, 320 * 240 * (4 + 288));
    let wide = RenderOptions {
        samples: 256,
        jitter: false,
    };
    let mut machine = Fake::with_gpu();
    // Room for every other technique's GPU frame (128 bytes a pixel), not for this one.
    machine.memory = Some(20_000_000);
    assert_eq!(
        placed(Technique::WedgesBlend, Backend::Gpu, wide, &mut machine),
        Placement::Gpu
    );
    let err = ask(Technique::DepthComplexity, Backend::Gpu, wide, &mut machine).unwrap_err();
    assert!(
        matches!(
            err,
            RenderError::OutOfMemory { needed, available: 20_000_000, .. }
                if needed == 9_830_400 + counting
        ),
        "{err}"
    );
    // Where the buffer fits, the GPU renders it; on the CPU it needs 16 bytes a pixel.
    machine.memory = Some(9_830_400 + counting);
    assert_eq!(
        placed(Technique::DepthComplexity, Backend::Gpu, wide, &mut machine),
        Placement::Gpu
    );
    machine.memory = Some(2_000_000);
    assert_eq!(
        placed(Technique::DepthComplexity, Backend::Cpu, wide, &mut machine),
        Placement::Cpu
    );
    // Fewer samples, a smaller buffer: 64 samples take 4 + 96 bytes a pixel.
    let mut machine = Fake::with_gpu();
    machine.memory = Some(9_830_400 + 320 * 240 * (4 + 96));
    let options = RenderOptions {
        samples: 64,
        jitter: false,
    };
    assert_eq!(
        placed(
            Technique::DepthComplexity,
            Backend::Gpu,
            options,
            &mut machine
        ),
        Placement::Gpu
    );
}

#[test]
fn library_messages_name_no_command_line_flag() {
    let mut machine = Fake::with_gpu();
    let errors = [
        ask(Technique::Pcf, Backend::Cpu, SMALL, &mut machine),
        ask(Technique::Reference, Backend::Gpu, SMALL, &mut machine),
        ask(
            Technique::DepthComplexity,
            Backend::Gpu,
            RenderOptions {
                samples: 4096,
                jitter: true,
            },
            &mut machine,
        ),
    ];
    for e in errors {
        let e = e.unwrap_err().to_string();
        assert!(!e.contains("--"), "{e}");
    }
}

#[test]
fn a_triangle_too_wide_for_the_gpu_goes_to_the_cpu_under_auto_only() {
    let wide = || Fake {
        extent: 2.0 * MAX_GPU_EXTENT_RATIO,
        ..Fake::with_gpu()
    };
    // Depth-complexity sampling stays on the CPU under Auto whatever the extent.
    for t in [Technique::Hard, Technique::Wedges, Technique::WedgesBlend] {
        let c = ask(t, Backend::Auto, SMALL, &mut wide()).unwrap();
        assert_eq!(c.placement, Placement::Cpu, "{t}");
        assert!(
            matches!(c.reason, Reason::WideTriangle { .. }),
            "{t}: {c:?}"
        );
        let c = ask(t, Backend::Gpu, SMALL, &mut wide()).unwrap();
        assert_eq!(c.placement, Placement::Gpu, "{t}");
        let c = ask(t, Backend::Auto, SMALL, &mut Fake::with_gpu()).unwrap();
        assert_eq!(c.placement, Placement::Gpu, "{t}");
    }
    let c = ask(Technique::DepthComplexity, Backend::Gpu, SMALL, &mut wide()).unwrap();
    assert_eq!(c.placement, Placement::Gpu);
    // The shadow maps have no CPU to go to.
    let c = ask(Technique::Pcss, Backend::Auto, SMALL, &mut wide()).unwrap();
    assert_eq!(c.placement, Placement::Gpu);
}
