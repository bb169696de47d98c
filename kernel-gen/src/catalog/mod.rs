//! The catalogue of generated kernels. For every registered Green's function: the self
//! and pair kernels of all nine blocks (a family file). For every scene (`scenes/`):
//! only the blocks its truncation needs, and, if asked, the fused pair products; a
//! building block ([`green::for_each_building_block`]) has its scenes' kernels only. In
//! `mod.rs`: the `Confinement` enum and the entry points that dispatch on it, using a
//! scene's kernels where one exists and the family's otherwise. In `single.rs`
//! ([`SINGLE`]): the FTS self and pair kernels of every family in single precision, behind
//! the `kernels` crate's feature `f32`. [`generate`] returns every file; `cargo xtask gen`
//! writes them, `--check` compares.
//!
//! - `scene`: [`Scene`], a scene file of `scenes/` ([`Moments`], [`Radii`]);
//! - `family`: the kernels of one Green's function ([`variants`], [`family()`]) and their
//!   single-precision twins;
//! - `scene_file`: the kernels of one scene ([`scene_file()`]);
//! - `twin`: a confinement that is an earlier one turned, served by its kernels (no file
//!   of its own);
//! - `dispatch`: the generated `mod.rs`, the `Confinement` enum and its entry points;
//! - `overlap`: the RPY overlap corrections of any confinement (`overlap.rs`);
//! - `expansion`: each confinement's far field as derivative sources of one potential,
//!   its mirrors and image weights, for a fast multipole method (`potential.rs`).

mod dispatch;
mod expansion;
mod family;
mod overlap;
mod scene;
mod scene_file;
mod twin;

pub use family::{family, variants, Variant, SINGLE};
pub use scene::{Moments, Radii, Scene, SceneError};
pub use scene_file::{scene_file, scene_file_of};

use crate::emit::{self, ident};
use crate::graph::{Ex, Id, Trace};
use crate::physics::green::{self, Green, Visitor};
use crate::physics::operators::Moment;
use crate::physics::potential;
use dispatch::dispatch;
use family::{family_and_single, single_files};
use proc_macro2::TokenStream;
use quote::quote;

/// One generated file: path relative to `kernels/src/generated/`, and contents.
pub struct GeneratedFile {
    /// File name, e.g. `wall.rs`.
    pub name: String,
    /// Contents.
    pub contents: String,
    /// Per-function operation counts, for the report: (function, total flops).
    pub op_counts: Vec<(String, usize)>,
}

impl GeneratedFile {
    /// Every function the file defines at its top level, in order: its name and the
    /// size in bytes of its code, from `pub fn` to its closing brace (doc comments and
    /// attributes left out). The size of what the compiler must digest, kernel by kernel:
    /// the file is formatted by prettyplease, which starts a top-level item in column 0
    /// and closes it with a `}` alone on a line.
    pub fn functions(&self) -> Vec<(&str, usize)> {
        let mut out = Vec::new();
        let mut open: Option<(&str, usize)> = None;
        let mut at = 0;
        for line in self.contents.split_inclusive('\n') {
            if let Some(rest) = line.strip_prefix("pub fn ") {
                let end = rest
                    .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .unwrap_or(rest.len());
                open = Some((&rest[..end], at));
            }
            at += line.len();
            if line.trim_end() == "}" {
                if let Some((name, start)) = open.take() {
                    out.push((name, at - start));
                }
            }
        }
        out
    }
}

/// Every generated file, including `mod.rs`, once every registered declaration passes
/// [`green::check_registry`].
pub fn generate(scenes: &[Scene]) -> Result<Vec<GeneratedFile>, green::DeclarationError> {
    green::check_registry()?;
    let mut c = Collect {
        families: Vec::new(),
        scenes,
        refused: None,
    };
    green::for_each(&mut c);
    let mut blocks = BuildingBlocks {
        scenes,
        files: Vec::new(),
    };
    green::for_each_building_block(&mut blocks);
    // (module, doc) of every file of kernels (the families', the scenes', the overlap
    // corrections'): declared in `bodies.rs` (the crate `kernel-bodies`), re-exported by
    // `mod.rs` (the crate `kernels`)
    let mut mods: Vec<(proc_macro2::Ident, String)> = Vec::new();
    if let Some((scene, green, of)) = c.refused {
        return Err(green::DeclarationError::SceneOfTwin { scene, green, of });
    }
    for f in c.families.iter().filter(|f| f.file.is_some()) {
        let n = ident(f.name);
        let d = format!(" Kernels of the `{}` family.", f.name);
        mods.push((n, d));
        for sf in &f.scene_files {
            let m = ident(sf.name.trim_end_matches(".rs"));
            let d = format!(
                " Kernels of the scene `{}` (`scenes/`).",
                sf.name.trim_start_matches("scene_").trim_end_matches(".rs")
            );
            mods.push((m, d));
        }
    }
    for (green, sf) in &blocks.files {
        let m = ident(sf.name.trim_end_matches(".rs"));
        let d = format!(
            " Kernels of the scene `{}` (`scenes/`) of the building block `{green}` (not a confinement: kernel_gen::physics::green::for_each_building_block).",
            sf.name.trim_start_matches("scene_").trim_end_matches(".rs")
        );
        mods.push((m, d));
    }
    mods.push((
        ident("overlap"),
        " The RPY overlap corrections (kernel_gen::physics::overlap).".to_string(),
    ));
    let declared = mods.iter().map(|(m, d)| quote!(#[doc = #d] pub mod #m;));
    let single_kernels = ident(family::SINGLE_KERNELS.trim_end_matches(".rs"));
    let reexported = mods
        .iter()
        .map(|(m, d)| quote!(#[doc = #d] pub use kernel_bodies::#m;));
    let dispatch = dispatch(&c.families);
    let potential = expansion::potential_file(&c.families);
    let single_entry = dispatch::single_dispatch(&c.families);
    let module_doc = vec![
        "Generated kernels, one module per Green's function.".to_string(),
        String::new(),
        "Regenerate with `cargo xtask gen`.".to_string(),
    ];
    let bodies_doc = vec![
        "The generated kernels' modules, compiled in the crate `kernel-bodies` (its".to_string(),
        "`lib.rs` includes this file) and re-exported by `mod.rs`.".to_string(),
    ];
    let mut files = vec![
        GeneratedFile {
            name: "mod.rs".into(),
            contents: emit::file(
                &module_doc,
                quote!(
                    #(#reexported)*
                    #[doc = " Each confinement's far field as derivative sources of the potential `|r|`, its mirrors and image weights (kernel_gen::physics::potential)."]
                    pub mod potential;
                    #dispatch
                ),
            ),
            op_counts: Vec::new(),
        },
        GeneratedFile {
            name: "bodies.rs".into(),
            contents: emit::file(
                &bodies_doc,
                quote!(
                    #(#declared)*
                    #[doc = " Single-precision FTS kernels of every family (the feature `f32`)."]
                    #[cfg(feature = "f32")]
                    pub mod #single_kernels;
                ),
            ),
            op_counts: Vec::new(),
        },
    ];
    let mut single = Vec::new();
    for f in c.families {
        files.extend(f.file);
        files.extend(f.scene_files);
        single.extend(f.single);
    }
    files.extend(blocks.files.into_iter().map(|(_, f)| f));
    files.extend(single_files(single_entry, single));
    files.push(overlap::overlap_file());
    files.push(GeneratedFile {
        name: "potential.rs".into(),
        contents: emit::file(
            &[
                "Each confinement's far field as derivative sources of the potential `|r|`, its mirrors".to_string(),
                "and image weights, for a fast multipole method (kernel_gen::physics::potential).".to_string(),
            ],
            potential,
        ),
        op_counts: Vec::new(),
    });
    Ok(files)
}

struct Family {
    name: &'static str,
    title: &'static str,
    params: &'static [green::Param],
    /// Each boundary plane, its offset an expression of the parameters.
    boundaries: Vec<green::Boundary<TokenStream>>,
    /// The normal of the cancelling image's plane, along which its pair kernels
    /// exchange the particles' roles ([`crate::kernel::Swap`]), if it has one.
    exchanges: Option<[f64; 3]>,
    /// Its kernels; `None` for a twin.
    file: Option<GeneratedFile>,
    /// Its single-precision self and pair kernels (items of [`SINGLE`]); `None` for a
    /// twin.
    single: Option<TokenStream>,
    /// The family whose kernels serve it, turned ([`twin`]), if it is a twin.
    twin: Option<twin::Twin>,
    /// Scenes of this confinement that serve the dispatch: `(moments, scene name)` of
    /// those with unequal radii and both outputs.
    serving: Vec<(Moments, String)>,
    scene_files: Vec<GeneratedFile>,
    /// Its far field for a fast multipole method.
    expansion: expansion::Expansion,
}

struct Collect<'a> {
    families: Vec<Family>,
    scenes: &'a [Scene],
    /// A scene of a twin: `(scene, twin, the family that serves it)`.
    refused: Option<(String, &'static str, &'static str)>,
}

impl Visitor for Collect<'_> {
    fn visit<G: Green>(&mut self, g: &G) {
        // The boundary heights as expressions of the parameters, traced and inlined.
        let t = Trace::begin();
        let p: Vec<Ex> = g.params().iter().map(|n| t.input(n.name)).collect();
        let b: Vec<green::Boundary<Id>> = g
            .boundaries(&p)
            .into_iter()
            .map(|b| green::Boundary {
                plane: green::Plane {
                    normal: b.plane.normal,
                    offset: b.plane.offset.0,
                },
                condition: b.condition,
                exact: b.exact,
            })
            .collect();
        let mirrors: Vec<([f64; 3], Id)> = g
            .mirrors(&p)
            .into_iter()
            .map(|m| (m.normal, m.offset.0))
            .collect();
        let weights: Vec<Id> = g.weights(&p).into_iter().map(|w| w.0).collect();
        let graph = t.finish();
        let expansion = expansion::Expansion {
            sources: potential::potential_sources(g, &[Moment::F]).and_then(|f| {
                Ok([
                    f,
                    potential::potential_sources(g, &[Moment::F, Moment::L])?,
                    potential::divergence_sources(g)?,
                ])
            }),
            mirrors: mirrors
                .into_iter()
                .map(|(n, o)| (n, emit::inline(&graph, o)))
                .collect(),
            weights: weights
                .into_iter()
                .map(|w| emit::inline(&graph, w))
                .collect(),
        };
        let boundaries = b
            .into_iter()
            .map(|b| green::Boundary {
                plane: green::Plane {
                    normal: b.plane.normal,
                    offset: emit::inline(&graph, b.plane.offset),
                },
                condition: b.condition,
                exact: b.exact,
            })
            .collect();
        let zeros = vec![0.0f64; g.params().len()];
        let exchanges = g
            .cancelling_image()
            .map(|(k, _)| g.mirrors(&zeros)[k].normal);
        let mine: Vec<&Scene> = self
            .scenes
            .iter()
            .filter(|s| s.confinement == g.name())
            .collect();
        let mut serving: Vec<(Moments, String)> = Vec::new();
        for s in &mine {
            let serves =
                s.radii == Radii::Unequal && s.dense && s.product && s.moments != Moments::FTS;
            if serves && !serving.iter().any(|(m, _)| *m == s.moments) {
                serving.push((s.moments, s.name.clone()));
            }
        }
        let twin = twin::find(g, &self.families);
        let (file, single, scene_files) = match &twin {
            Some(t) => {
                // a twin: the serving family's scenes serve it; one of its own is refused
                if let Some(s) = mine.first() {
                    self.refused.get_or_insert((s.name.clone(), g.name(), t.of));
                }
                serving = (self.families.iter())
                    .find(|f| f.name == t.of)
                    .map(|f| f.serving.clone())
                    .unwrap_or_default();
                (None, None, Vec::new())
            }
            None => {
                let (file, single) = family_and_single(g);
                let scenes = mine.iter().map(|s| scene_file(g, s, false)).collect();
                (Some(file), Some(single), scenes)
            }
        };
        self.families.push(Family {
            name: g.name(),
            title: g.title(),
            params: g.params(),
            exchanges,
            boundaries,
            file,
            single,
            twin,
            serving,
            scene_files,
            expansion,
        });
    }
}

/// The scene files of the building blocks ([`green::for_each_building_block`]): their
/// only kernels.
struct BuildingBlocks<'a> {
    scenes: &'a [Scene],
    /// `(Green's function, scene file)`.
    files: Vec<(&'static str, GeneratedFile)>,
}

impl Visitor for BuildingBlocks<'_> {
    fn visit<G: Green>(&mut self, g: &G) {
        for s in self.scenes.iter().filter(|s| s.confinement == g.name()) {
            self.files.push((g.name(), scene_file(g, s, false)));
        }
    }
}

/// The kernels' return type for a truncation.
fn blocks_type(m: Moments) -> &'static str {
    match m {
        Moments::F => "BlocksF",
        Moments::FT => "BlocksFT",
        Moments::FTS => "Grand",
    }
}

fn moments_label(m: Moments) -> &'static str {
    match m {
        Moments::F => "F",
        Moments::FT => "FT",
        Moments::FTS => "FTS",
    }
}
