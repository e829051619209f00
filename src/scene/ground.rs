//! `[ground]`: how far the ground is drawn clear, and its height field
//! (src/model/terrain.rs): a grey PNG height map and hills and ridges
//! written by hand, summed. Flat by default.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::check::{self, Check, FieldError};
use super::grey_png;
use crate::model::terrain::{HeightMap, Hill, Ridge, Terrain};

/// The ground: a height field out to the horizon (flat: the plane y = 0).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Ground {
    /// How far from the grass's centre the ground is clear (m); beyond,
    /// it fades into the sky's horizon colour (glsl/backdrop/ground.frag).
    pub half_extent: f32,
    /// A grey PNG (8 or 16 bit) of heights, relative to the scene file:
    /// column 0 at the map's least x, row 0 at its least z; black 0 m,
    /// white `vertical_scale` m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub height_map: Option<FileName>,
    /// The ground the height map covers (x, z metres); needed with one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub extent: Option<[f32; 2]>,
    /// Where the height map's centre lies (x, z); the origin by default.
    #[serde(skip_serializing_if = "is_origin")]
    pub map_center: [f32; 2],
    /// Metres of height that white stands for.
    #[serde(skip_serializing_if = "is_one")]
    pub vertical_scale: f32,
    #[serde(rename = "hill", skip_serializing_if = "Vec::is_empty")]
    pub hills: Vec<Hill>,
    #[serde(rename = "ridge", skip_serializing_if = "Vec::is_empty")]
    pub ridges: Vec<Ridge>,
    /// The height map read (`Ground::read_files`), not part of the file.
    #[serde(skip)]
    pub map: Option<Arc<HeightMap>>,
}

fn is_origin(c: &[f32; 2]) -> bool {
    *c == [0.0, 0.0]
}

fn is_one(v: &f32) -> bool {
    *v == 1.0
}

impl Default for Ground {
    fn default() -> Self {
        Self {
            half_extent: 10.0,
            height_map: None,
            extent: None,
            map_center: [0.0, 0.0],
            vertical_scale: 1.0,
            hills: Vec::new(),
            ridges: Vec::new(),
            map: None,
        }
    }
}

/// Where the files a scene names are found.
#[derive(Clone, Copy, Debug)]
pub enum SceneFiles<'a> {
    /// Beside the scene file, in this folder.
    Dir(&'a Path),
    /// Compiled in with the built-in scenes (`scenes/`).
    Builtin,
}

/// The images the built-in scenes name, compiled in.
const BUILTIN_FILES: &[(&str, &[u8])] = &[(
    "hills-path.png",
    include_bytes!("../../scenes/hills-path.png"),
)];

/// The highest ground or deepest hollow a scene may have (m).
pub const MAX_RELIEF: f32 = 1000.0;

impl Ground {
    /// The same ground made flat: its clear radius kept, its terrain gone.
    pub fn flattened(&self) -> Self {
        Self {
            half_extent: self.half_extent,
            ..Self::default()
        }
    }

    /// The ground's height field, as read.
    pub fn terrain(&self) -> Terrain {
        Terrain {
            map: self.map.clone(),
            hills: self.hills.clone(),
            ridges: self.ridges.clone(),
        }
    }

    /// Reads the height map the ground names (refusing it by field, with
    /// the fix), after `check` passed.
    pub fn read_files(&mut self, files: SceneFiles<'_>) -> Check {
        let Some(name) = &mut self.height_map else {
            self.map = None;
            return Ok(());
        };
        let grey = read_grey(&name.written, files).map_err(|e| FieldError::new("height_map", e))?;
        name.found_in(files);
        let extent = self.extent.expect("checked: a height map has its extent");
        self.map = Some(Arc::new(HeightMap {
            columns: grey.width,
            rows: grey.height,
            heights: grey
                .values
                .iter()
                .map(|v| v * self.vertical_scale)
                .collect(),
            extent,
            center: self.map_center,
        }));
        Ok(())
    }

    /// Every field in its range; a height map with its extent.
    pub fn check(&self) -> Check {
        check::positive("half_extent", self.half_extent, 10_000.0)?;
        match (&self.height_map, self.extent) {
            (Some(name), _) if name.written.trim().is_empty() => {
                return Err(FieldError::new(
                    "height_map",
                    "is empty; name a grey PNG relative to the scene file",
                ))
            }
            (Some(_), None) => return Err(FieldError::new(
                "extent",
                "is missing: a height map needs the ground it covers, extent = [x, z] in metres",
            )),
            _ => {}
        }
        if let Some([x, z]) = self.extent {
            check::positive("extent[0]", x, 100_000.0)?;
            check::positive("extent[1]", z, 100_000.0)?;
        }
        check::finite("map_center", &self.map_center)?;
        check::within(
            "vertical_scale",
            self.vertical_scale,
            0.0..=MAX_RELIEF,
            "0..=1000 m",
        )?;
        for (i, h) in self.hills.iter().enumerate() {
            feature(h.center, h.height, h.half_width).map_err(|e| e.at(&format!("hill[{i}]")))?;
        }
        for (i, r) in self.ridges.iter().enumerate() {
            feature(r.center, r.height, r.half_width)
                .and_then(|()| {
                    check::within("heading", r.heading, -360.0..=360.0, "-360..=360 degrees")
                })
                .map_err(|e| e.at(&format!("ridge[{i}]")))?;
        }
        Ok(())
    }
}

fn feature(center: [f32; 2], height: f32, half_width: f32) -> Check {
    check::finite("center", &center)?;
    check::within("height", height, -MAX_RELIEF..=MAX_RELIEF, "-1000..=1000 m")?;
    check::positive("half_width", half_width, 100_000.0)
}

/// The grey image `name` names: a file beside the scene, or a built-in
/// scene's compiled-in image (also for a scene file that names one and
/// has no file of that name beside it: a copy of a built-in scene).
/// A file a scene names (a height map, a mask): the name as written, and
/// where it was found when that was beside the scene file by a relative
/// name. Scenes compare by the name as written; a scene is saved (the
/// scene.toml beside a run) with where it was found, so the saved scene
/// finds the file from anywhere.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(from = "String", into = "String")]
pub struct FileName {
    pub written: String,
    pub found: Option<String>,
}

impl FileName {
    /// Notes where the file was read from `files`: its absolute path when
    /// found beside a scene file by a relative name (not a built-in
    /// scene's image, which is found by its name anywhere).
    pub(super) fn found_in(&mut self, files: SceneFiles<'_>) {
        let name = Path::new(&self.written);
        if let SceneFiles::Dir(dir) = files {
            if name.is_relative() && dir.join(name).exists() {
                self.found = std::path::absolute(dir.join(name))
                    .ok()
                    .map(|p| p.display().to_string());
            }
        }
    }
}

impl PartialEq for FileName {
    fn eq(&self, other: &Self) -> bool {
        self.written == other.written
    }
}

impl From<String> for FileName {
    fn from(written: String) -> Self {
        Self {
            written,
            found: None,
        }
    }
}

impl From<FileName> for String {
    fn from(f: FileName) -> Self {
        f.found.unwrap_or(f.written)
    }
}

pub(super) fn read_grey(
    name: &str,
    files: SceneFiles<'_>,
) -> std::result::Result<grey_png::Grey, String> {
    let builtin = || {
        let Some((_, bytes)) = BUILTIN_FILES.iter().find(|(n, _)| *n == name) else {
            return Err(format!("{name}: no built-in scene image has this name"));
        };
        grey_png::read_bytes(bytes).map_err(|why| format!("{name}: {why}"))
    };
    match files {
        SceneFiles::Dir(dir) => {
            let path: PathBuf = dir.join(name);
            // A copy of a built-in scene finds its images by name.
            if !path.exists() && BUILTIN_FILES.iter().any(|(n, _)| *n == name) {
                return builtin();
            }
            grey_png::read(&path).map_err(|why| format!("{}: {why}", path.display()))
        }
        SceneFiles::Builtin => builtin(),
    }
}
