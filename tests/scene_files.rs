//! Scene files: the shipped ones parse and are the built-ins, built-ins
//! survive a round trip through TOML, and malformed files are refused with
//! one line naming the file, line, column, field and allowed range.

use meadow::scene::{file, Scene, BUILTIN};

/// The smallest complete scene; the cases below break it one way each.
const MINIMAL: &str = r#"name = "minimal"
seed = 1

[camera]
position = [0.0, 1.0, 3.0]
target = [0.0, 0.0, 0.0]
fov_y = 45.0

[[grass.bunch]]
center = [0.0, 0.0]
radius = 0.2
count = 10
"#;

#[test]
fn the_minimal_scene_is_valid_and_fills_in_defaults() {
    let scene = file::parse(MINIMAL, "minimal.toml").expect("minimal scene");
    assert_eq!(scene.blade_count(), 10);
    assert_eq!(scene.render.width, 1280);
    assert_eq!(scene.wind.cells, [60, 20, 60]);
    assert_eq!(scene.wind.jacobi_iterations, 30);
    assert!(scene.wind.inflow.is_none());
}

/// Every field of an optional table is optional on its own: what is
/// written is taken, the rest keeps the documented default.
#[test]
fn optional_tables_take_each_field_on_its_own() {
    let defaults = file::parse(MINIMAL, "minimal.toml").unwrap();
    let ambient_only = file::parse(&plus("[light]\nambient = 0.5"), "light.toml")
        .unwrap_or_else(|e| panic!("[light] with only ambient: {e}"));
    assert_eq!(ambient_only.light.ambient, 0.5);
    assert_eq!(ambient_only.light.direction, defaults.light.direction);
    assert_eq!(ambient_only.light.color, defaults.light.color);
    assert_eq!(ambient_only.light.shadow_map, 8192);
    let map_only = file::parse(&plus("[light]\nshadow_map = 1024"), "light.toml")
        .unwrap_or_else(|e| panic!("[light] with only shadow_map: {e}"));
    assert_eq!(map_only.light.shadow_map, 1024);
    assert_eq!(map_only.light.ambient, defaults.light.ambient);
    let gust = plus("[wind.inflow]\nspeed = 2.0\ngust = { amplitude = 0.5, frequency = 0.3 }");
    let gust = file::parse(&gust, "gust.toml")
        .unwrap_or_else(|e| panic!("a gust without a seed: {e}"))
        .wind
        .inflow
        .expect("inflow")
        .gust;
    assert_eq!((gust.amplitude, gust.frequency, gust.seed), (0.5, 0.3, 0));
    let ground = file::parse(&plus("[ground]"), "ground.toml")
        .unwrap_or_else(|e| panic!("an empty [ground]: {e}"));
    assert_eq!(ground.ground, defaults.ground);
}

#[test]
fn shipped_scene_files_are_the_builtins() {
    for (name, _) in BUILTIN {
        let path = format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let from_file = Scene::load(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert_eq!(from_file, Scene::builtin(name).unwrap(), "{name}");
        assert_eq!(&from_file.name, name);
        assert!(!from_file.caption.is_empty(), "{name} has no caption");
    }
}

#[test]
fn builtins_survive_a_round_trip_through_toml() {
    for (name, _) in BUILTIN {
        let scene = Scene::builtin(name).unwrap();
        let text = file::to_toml(&scene);
        let back = file::parse(&text, name).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        assert_eq!(back, scene, "{name}");
    }
    // Meadows given by density and keyframed cameras too.
    let mut scene = file::parse(MINIMAL, "minimal.toml").unwrap();
    scene.grass.meadow.push(meadow::scene::Meadow {
        center: [1.0, 2.0],
        size: [3.0, 4.0],
        count: None,
        density: Some(12.5),
        mask: None,
        mask_map: None,
    });
    scene.camera.path.push(meadow::scene::CameraKey {
        time: 1.5,
        position: [1.0, 1.0, 1.0],
        target: [0.0, 0.1, 0.0],
    });
    let back = file::parse(&file::to_toml(&scene), "again").unwrap();
    assert_eq!(back, scene);
}

/// Replaces `from` (which must occur) by `to` in the minimal scene.
fn with(from: &str, to: &str) -> String {
    assert!(MINIMAL.contains(from), "{from:?} not in the minimal scene");
    MINIMAL.replacen(from, to, 1)
}

fn plus(extra: &str) -> String {
    format!("{MINIMAL}\n{extra}\n")
}

#[test]
fn malformed_scene_files_are_refused_with_line_column_field_and_range() {
    // (what is wrong, the file, the line the error must point at, the
    // message fragment expected after "bad.toml:LINE:COLUMN: ").
    let cases: Vec<(&str, String, usize, &str)> = vec![
        (
            "empty file",
            String::new(),
            1,
            "missing field `name` (the file is empty; docs/scenes.md has a complete example)",
        ),
        (
            "wrong type",
            with("seed = 1", "seed = \"one\""),
            2,
            "seed: invalid type: string \"one\", expected a whole number, 0 or more",
        ),
        (
            "unknown top-level key",
            with("seed = 1", "seed = 1\ncolour = 3"),
            3,
            "colour: unknown field `colour`, expected one of `name`",
        ),
        (
            "unknown key in a section",
            plus("[grass.shape]\nhue = 0.3"),
            15,
            "grass.shape.hue: unknown field `hue`",
        ),
        (
            "missing section",
            MINIMAL.replace("[camera]\nposition = [0.0, 1.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y = 45.0\n", ""),
            1,
            "missing field `camera`",
        ),
        (
            "no grass patch",
            MINIMAL.replace("[[grass.bunch]]\ncenter = [0.0, 0.0]\nradius = 0.2\ncount = 10\n", "[grass]\n"),
            9,
            "grass: the scene has no grass; add a [[grass.bunch]], a [[grass.meadow]] or a [grass.cover]",
        ),
        (
            "zero count",
            with("count = 10", "count = 0"),
            12,
            "grass.bunch[0].count: 0 is not allowed, use 1..=10000000",
        ),
        (
            "huge count",
            with("count = 10", "count = 99999999999"),
            12,
            "grass.bunch[0].count: 99999999999 is not allowed, use 1..=10000000",
        ),
        (
            "negative count",
            with("count = 10", "count = -5"),
            12,
            "grass.bunch[0].count: invalid value: integer `-5`, expected a whole number, 0 or more",
        ),
        (
            "negative radius",
            with("radius = 0.2", "radius = -1.0"),
            11,
            "grass.bunch[0].radius: -1 is not allowed, use a number above 0 and at most 10000",
        ),
        (
            "NaN",
            plus("[wind.inflow]\nspeed = nan"),
            15,
            "wind.inflow.speed: [NaN] is not allowed, every value must be a finite number",
        ),
        (
            "infinite field of view",
            with("fov_y = 45.0", "fov_y = inf"),
            7,
            "camera.fov_y: inf is not allowed, use 1 < fov_y < 170 degrees",
        ),
        (
            "reversed range",
            plus("[grass.shape]\nheight = [0.8, 0.3]"),
            15,
            "grass.shape.height: [0.8, 0.3] is reversed, write [min, max]",
        ),
        (
            "zero image width",
            plus("[render]\nwidth = 0"),
            15,
            "render.width: 0 is not allowed, use 1..=16384",
        ),
        (
            "MSAA that is not a sample count",
            plus("[render]\nmsaa = 3"),
            15,
            "render.msaa: 3 is not a sample count, use 1, 2, 4, 8, 16, 32 or 64",
        ),
        (
            "unknown view",
            plus("[render]\nview = \"xray\""),
            15,
            "render.view: unknown variant `xray`, expected one of `shaded`, `lod`, `motion`",
        ),
        (
            "meadow with count and density",
            plus("[[grass.meadow]]\ncenter = [0.0, 0.0]\nsize = [2.0, 2.0]\ncount = 5\ndensity = 3.0"),
            14,
            "grass.meadow[0]: has both count and density; give one of them",
        ),
        (
            "meadow density giving too many blades",
            plus("[[grass.meadow]]\ncenter = [0.0, 0.0]\nsize = [1000.0, 1000.0]\ndensity = 50.0"),
            17,
            "grass.meadow[0].density: 50 per square metre gives 50000000 blades",
        ),
        (
            "zero wind cells",
            plus("[wind]\ncells = [60, 0, 60]"),
            15,
            "wind.cells[1]: 0 is not allowed, use 1..=4096",
        ),
        (
            "too many wind cells",
            plus("[wind]\ncells = [4096, 4096, 10]"),
            15,
            "wind.cells: 167772160 cells is not allowed, use at most 67108864",
        ),
        (
            "simulation step too long",
            plus("[wind]\ndt = 0.5"),
            15,
            "wind.dt: 0.5 is not allowed, use a number above 0 and at most 0.1",
        ),
        (
            "negative stiffness range",
            plus("[grass.dynamics]\ntip_stiffness = [-1.0, 0.01]"),
            15,
            "grass.dynamics.tip_stiffness: a range reaching -1 is not allowed, use > 0 N/rad",
        ),
        (
            "unknown wind source key",
            plus("[[wind.source]]\nposition = [0.0, 0.5, 0.0]\ndirection = [1.0, 0.0, 0.0]\nstrength = 5.0\nradius = 1.0\nspin = 2.0"),
            19,
            "wind.source[0].spin: unknown field `spin`",
        ),
        (
            "wind source radius zero",
            plus("[[wind.source]]\nposition = [0.0, 0.5, 0.0]\ndirection = [1.0, 0.0, 0.0]\nstrength = 5.0\nradius = 0.0"),
            18,
            "wind.source[0].radius: 0 is not allowed, use a number above 0",
        ),
        (
            "unknown obstacle kind",
            plus("[[wind.obstacle]]\nkind = \"cone\""),
            15,
            "wind.obstacle[0].kind: unknown variant `cone`, expected one of `box`, `sphere`, `cylinder`",
        ),
        (
            "inside-out box",
            plus("[[wind.obstacle]]\nkind = \"box\"\nmin = [1.0, 0.0, 1.0]\nmax = [0.0, 1.0, 2.0]"),
            17,
            "wind.obstacle[0].max: [0, 1, 2] is not above min [1, 0, 1] on every axis",
        ),
        (
            "camera looking at itself",
            with("target = [0.0, 0.0, 0.0]", "target = [0.0, 1.0, 3.0]"),
            6,
            "camera.target: equals the position; the camera must look somewhere",
        ),
        (
            "camera keyframes out of order",
            plus("[[camera.path]]\ntime = 2.0\nposition = [0.0, 1.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n[[camera.path]]\ntime = 1.0\nposition = [0.0, 1.0, 4.0]\ntarget = [0.0, 0.0, 0.0]"),
            19,
            "camera.path[1].time: 1 is not after the previous key's 2; keyframe times must increase",
        ),
        (
            "LOD distances reversed",
            plus("[lod]\nclose_distance = 9.0\nfar_distance = 4.0"),
            16,
            "lod.far_distance: 4 is nearer than close_distance 9; use close <= far",
        ),
        (
            "a negative shadow tolerance in pixels",
            plus("[lod]\nshadow_error_pixels = -1.0"),
            15,
            "lod.shadow_error_pixels: -1 is not allowed, use 0 (the texels' bound alone) to 64",
        ),
        (
            "thinning keeping no blade",
            plus("[cull]\nthin_least = 0.0"),
            15,
            "cull.thin_least: 0 is not allowed, use a share in 0.01..=1 (1 keeps every blade)",
        ),
        (
            "orientation test leaving out face-on blades",
            plus("[cull]\nedge_on = 0.2"),
            15,
            "cull.edge_on: 0.2 is not allowed, use a cosine in 0.5..=1 (1 keeps blades seen edge-on)",
        ),
        (
            "syntax error",
            with("seed = 1", "seed = "),
            2,
            "string values must be quoted",
        ),
        (
            "ambient out of range",
            plus("[light]\ndirection = [0.0, 1.0, 0.0]\ncolor = [1.0, 1.0, 1.0]\nambient = 2.0"),
            17,
            "light.ambient: 2 is not allowed, use 0..=1",
        ),
        (
            "no grass at all: the top level lacks it, no field is blamed",
            MINIMAL.replace("[[grass.bunch]]\ncenter = [0.0, 0.0]\nradius = 0.2\ncount = 10\n", ""),
            1,
            "bad.toml:1:1: missing field `grass`",
        ),
        (
            "a key written twice is named",
            with("seed = 1", "seed = 1\nseed = 2"),
            3,
            "duplicate key `seed`; write each key once per table",
        ),
        (
            "a number where text is not: no Rust type names",
            with("radius = 0.2", "radius = \"wide\""),
            11,
            "grass.bunch[0].radius: invalid type: string \"wide\", expected a number",
        ),
        (
            "a source pushing in no direction",
            plus("[[wind.source]]\nposition = [0.0, 0.5, 0.0]\ndirection = [0.0, 0.0, 0.0]\nstrength = 5.0\nradius = 1.0"),
            16,
            "wind.source[0].direction: is zero",
        ),
        (
            "a path speed without a path",
            plus("[[wind.source]]\nposition = [0.0, 0.5, 0.0]\ndirection = [1.0, 0.0, 0.0]\nstrength = 5.0\nradius = 1.0\npath_speed = 2.0"),
            19,
            "wind.source[0].path_speed: moves it along its path, which needs at least 2 points",
        ),
        // Too long is refused as too short is (serde alone would drop the
        // extra values silently).
        (
            "bunch centre with three values",
            with("center = [0.0, 0.0]", "center = [1.0, 0.0, 2.0]"),
            10,
            "grass.bunch[0].center: has 3 values, use exactly 2",
        ),
        (
            "camera position with four values",
            with("position = [0.0, 1.0, 3.0]", "position = [0.0, 1.0, 3.0, 1.0]"),
            5,
            "camera.position: has 4 values, use exactly 3",
        ),
        (
            "four LOD levels",
            plus("[lod]\nlevels = [20, 10, 3, 1]"),
            15,
            "lod.levels: has 4 values, use exactly 3",
        ),
        (
            "four wind cell counts",
            plus("[wind]\ncells = [10, 10, 10, 10]"),
            15,
            "wind.cells: has 4 values, use exactly 3",
        ),
        (
            "a source path point with four values",
            plus("[[wind.source]]\nposition = [0.0, 0.5, 0.0]\ndirection = [1.0, 0.0, 0.0]\nstrength = 5.0\nradius = 1.0\npath = [[0.0, 0.5, 0.0], [1.0, 0.5, 0.0, 7.0]]"),
            19,
            "wind.source[0].path[1]: has 4 values, use exactly 3",
        ),
        (
            "a sphere with a height",
            plus("[[collider]]\nkind = \"sphere\"\nradius = 0.3\nheight = 1.0\nposition = [0.0, 0.3, 0.0]"),
            17,
            "collider[0].height: is for capsules",
        ),
        (
            "a ball sunk into the ground",
            plus("[[collider]]\nkind = \"sphere\"\nradius = 0.3\nposition = [0.0, 0.1, 0.0]"),
            17,
            "collider[0].position: reaches 0.200 m below the ground",
        ),
        (
            "a rolling capsule",
            plus("[[collider]]\nkind = \"capsule\"\nradius = 0.3\nheight = 1.0\nroll = true"),
            18,
            "collider[0].roll: is for spheres",
        ),
        (
            "a collider setting off before time begins",
            plus("[[collider]]\nkind = \"sphere\"\nradius = 0.3\nposition = [0.0, 0.3, 0.0]\nstart = -1.0"),
            18,
            "collider[0].start: -1 is not allowed, use 0 ..= 1e6 s",
        ),
        (
            "a camera under the ground",
            with("position = [0.0, 1.0, 3.0]", "position = [0.0, -1.0, 3.0]"),
            5,
            "camera.position: is 1 m under the ground (y < 0); raise it to y >= 0",
        ),
        (
            "a camera beyond the view's reach of the grass",
            with("position = [0.0, 1.0, 3.0]", "position = [0.0, 1.0, 1e7]"),
            5,
            "camera.position: is 9999999 m from the nearest grass and the view reaches 200 m",
        ),
        (
            "a light from below the horizon",
            plus("[light]\ndirection = [0.0, -1.0, 0.0]"),
            15,
            "light.direction: [0.0, -1.0, 0.0] points below the horizon",
        ),
        (
            "a collider placed twice",
            plus("[[collider]]\nkind = \"sphere\"\nradius = 0.3\nposition = [1.0, 0.3, 0.0]\npath = [[0.0, 0.3, 0.0], [2.0, 0.3, 0.0]]\npath_speed = 1.0"),
            17,
            "collider[0].position: and path both place it",
        ),
        (
            "a collider placed nowhere",
            plus("[[collider]]\nkind = \"sphere\"\nradius = 0.3"),
            14,
            "collider[0].position: is missing (or the origin), which puts it under the ground",
        ),
        (
            "a source switched off before time begins",
            plus("[[wind.source]]\nposition = [0.0, 0.5, 0.0]\ndirection = [1.0, 0.0, 0.0]\nstrength = 5.0\nradius = 1.0\noff_after = -1.0"),
            19,
            "wind.source[0].off_after: -1 is not allowed, use a time of 0 s or more",
        ),
        (
            "a collider faster than anything the grid could follow",
            plus("[[collider]]\nkind = \"sphere\"\nradius = 0.3\npath = [[0.0, 0.3, 0.0], [2.0, 0.3, 0.0]]\npath_speed = 1e9"),
            18,
            "collider[0].path_speed: 1000000000 is not allowed, use 0 ..= 1000 m/s",
        ),
    ];
    assert!(cases.len() >= 15);
    let mut wrong = Vec::new();
    for (what, text, line, fragment) in &cases {
        let result = std::panic::catch_unwind(|| file::parse(text, "bad.toml"));
        let err = match result {
            Ok(Ok(_)) => {
                wrong.push(format!("{what}: accepted"));
                continue;
            }
            Ok(Err(e)) => e.to_string(),
            Err(_) => {
                wrong.push(format!("{what}: panicked"));
                continue;
            }
        };
        let prefix = format!("bad.toml:{line}:");
        if err.lines().count() != 1 || !err.starts_with(&prefix) || !err.contains(fragment) {
            wrong.push(format!(
                "{what}: {err:?} is not one line starting {prefix:?} with {fragment:?}"
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The camera, its path and the colliders are held over the ground where
/// they are, not over y = 0: inside a hill (or passing through one between
/// two keys over it) they are refused naming the ground's height there; in
/// a hollow, under y = 0 but over its floor, they are accepted.
#[test]
fn the_camera_and_colliders_are_checked_against_the_ground_where_they_stand() {
    // A hill 2 m high centred under the camera (x 0, z 3).
    let hill = |height: f32, camera_y: f32, extra: &str| {
        let text = with(
            "position = [0.0, 1.0, 3.0]",
            &format!("position = [0.0, {camera_y:?}, 3.0]"),
        );
        format!("{text}\n[[ground.hill]]\ncenter = [0.0, 3.0]\nheight = {height:?}\nhalf_width = 2.5\n{extra}\n")
    };
    let refused = |text: &str, fragment: &str| {
        let e = file::parse(text, "hill.toml")
            .expect_err(fragment)
            .to_string();
        assert!(
            e.lines().count() == 1 && e.contains(fragment),
            "{e:?} lacks {fragment:?}"
        );
    };
    let accepted = |text: &str, what: &str| {
        file::parse(text, "hill.toml").unwrap_or_else(|e| panic!("{what}: {e}"));
    };
    refused(
        &hill(2.0, 1.0, ""),
        "hill.toml:5:12: camera.position: is 1.00 m under the ground, whose surface at x 0.0, z 3.0 is at y 2.00; raise it to y >= 2.00",
    );
    accepted(&hill(2.0, 2.5, ""), "a camera over the hill's top");
    accepted(
        &hill(-2.0, -1.5, ""),
        "a camera in a hollow, over its floor",
    );
    refused(
        &hill(-2.0, -2.5, ""),
        "camera.position: is 0.50 m under the ground, whose surface at x 0.0, z 3.0 is at y -2.00",
    );
    // Two keys clear of the hill, the line between them through it.
    let path =
        "[[camera.path]]\ntime = 0.0\nposition = [-6.0, 1.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n\
                [[camera.path]]\ntime = 2.0\nposition = [6.0, 1.0, 3.0]\ntarget = [0.0, 0.0, 0.0]";
    refused(
        &hill(2.0, 2.5, path),
        "camera.path: passes 1.00 m under the ground between path[0] and path[1] (deepest at x 0.0, z 3.0",
    );
    let ball = |y: f32, x: f32| {
        format!("[[collider]]\nkind = \"sphere\"\nradius = 0.3\nposition = [{x:?}, {y:?}, 3.0]")
    };
    accepted(
        &hill(2.0, 3.0, &ball(2.3, 0.0)),
        "a ball resting on the hill's top",
    );
    // On the flank, 0.3 m over the ground under its centre: its uphill
    // side is in the hill.
    let flank = 2.0 / (1.0 + (2.5f32 / 2.5).powi(2));
    refused(
        &hill(2.0, 3.0, &ball(flank + 0.3, 2.5)),
        "collider[0].position: reaches 0.0",
    );
    accepted(
        &hill(-2.0, 0.5, &ball(-1.7, 0.0)),
        "a ball resting in a hollow, under y = 0",
    );
}

#[test]
fn unreadable_files_name_the_path() {
    let dir = std::env::temp_dir().join(format!("meadow-scene-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let missing = dir.join("missing.toml");
    let e = Scene::load(missing.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("missing.toml") && e.contains("No such file"),
        "{e}"
    );
    let binary = dir.join("binary.toml");
    std::fs::write(&binary, [0x6e, 0x61, 0xff, 0xfe, 0x00]).unwrap();
    let e = Scene::load(binary.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("binary.toml: not UTF-8 text (byte 2)"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_documented_example_is_a_valid_scene_using_every_section() {
    let doc =
        std::fs::read_to_string(format!("{}/docs/scenes.md", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let start = doc.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let text = &doc[start..start + doc[start..].find("```").unwrap()];
    let scene = file::parse(text, "docs/scenes.md").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.camera.path.len(), 2);
    assert_eq!(scene.grass.bunch.len() + scene.grass.meadow.len(), 2);
    assert_eq!(scene.wind.sources.len(), 1);
    assert_eq!(scene.wind.obstacles.len(), 3);
    assert!(scene.wind.inflow.is_some());
    // Every field it sets is a field the scene has: printing the parsed
    // scene back gives every key the example uses.
    let printed = file::to_toml(&scene);
    for line in text.lines() {
        let line = line.trim();
        if let Some((key, value)) = line.split_once(" = ") {
            // Inline tables come back as sub-tables: skip those keys.
            if !key.starts_with('#') && !value.starts_with('{') {
                assert!(
                    printed.contains(&format!("{key} =")),
                    "{key} not printed back"
                );
            }
        }
    }
}

/// Nothing grows inside an obstacle: no root of fig13's field lies in its
/// wall, boulder or post, where the same meadow without them has roots.
#[test]
fn no_blade_is_rooted_inside_an_obstacle() {
    let scene = Scene::builtin("fig13-obstacles").unwrap();
    let obstacles = scene.wind.obstacles.clone();
    assert_eq!(obstacles.len(), 3);
    let inside = |blades: &[meadow::model::Blade]| {
        blades
            .iter()
            .filter(|b| {
                let root = b.rest[0] + glam::Vec3::Y * 0.01;
                obstacles.iter().any(|o| o.contains(root))
            })
            .count()
    };
    let with = scene.field().unwrap();
    let mut open = scene.clone();
    open.wind.obstacles.clear();
    let without = open.field().unwrap();
    eprintln!(
        "fig13: {} of {} blades would be rooted inside an obstacle",
        inside(&without),
        without.len()
    );
    assert!(inside(&without) > 100);
    assert_eq!(inside(&with), 0);
    assert_eq!(with.len(), without.len() - inside(&without));
}

/// `wind.turbulence` refused in one line naming the field and what is
/// allowed: each number out of its range or not finite, no reference speed
/// without an inflow, and (on the wind grid) a length scale smaller than a
/// cell or larger than the grid.
#[test]
fn bad_turbulence_is_refused_naming_the_field() {
    let turbulent = |table: &str, inflow: bool| {
        let inflow = if inflow {
            "[wind.inflow]\nspeed = 3.0\n"
        } else {
            ""
        };
        plus(&format!("[wind]\nturbulence = {{ {table} }}\n{inflow}"))
    };
    for (table, inflow, expected) in [
        (
            "intensity = -0.3, length_scale = 1.0",
            true,
            "wind.turbulence.intensity: -0.3 is not allowed, use a number above 0 and at most 2",
        ),
        (
            "intensity = nan, length_scale = 1.0",
            true,
            "wind.turbulence.intensity: NaN is not allowed",
        ),
        (
            "intensity = 0.3, length_scale = 0.0",
            true,
            "wind.turbulence.length_scale: 0 is not allowed, use a number above 0",
        ),
        (
            "intensity = 0.3, length_scale = inf",
            true,
            "wind.turbulence.length_scale: inf is not allowed",
        ),
        (
            "intensity = 0.3, length_scale = 1.0",
            false,
            "wind.turbulence.speed: missing: without an inflow it is needed",
        ),
        (
            "intensity = 0.3, length_scale = 1.0, speed = -2.0",
            false,
            "wind.turbulence.speed: -2 is not allowed",
        ),
        (
            "intensity = 0.3, length_scale = 1.0, finest_wavelength = 0.0",
            true,
            "wind.turbulence.finest_wavelength: 0 is not allowed, use a number above 0",
        ),
    ] {
        let err = file::parse(&turbulent(table, inflow), "bad.toml")
            .err()
            .unwrap_or_else(|| panic!("{table} was accepted"))
            .to_string();
        assert!(err.contains(expected), "{table}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    // The minimal scene's wind grid: 3.4 m across, cells 0.06 x 0.15 x 0.06 m.
    for (length, expected) in [
        ("0.1", "0.1 m is not allowed"),
        ("5.0", "5 m is not allowed"),
    ] {
        let scene = file::parse(
            &turbulent(&format!("intensity = 0.3, length_scale = {length}"), true),
            "t.toml",
        )
        .unwrap();
        let err = scene.wind_grid().err().unwrap().to_string();
        assert!(
            err.contains(&format!(
                "wind.turbulence.length_scale {expected} on this wind grid, use 0.15..=3.4 m"
            )),
            "{err}"
        );
    }
    let fine = file::parse(
        &turbulent("intensity = 0.3, length_scale = 1.0", true),
        "t.toml",
    );
    assert!(fine.unwrap().wind_grid().is_ok());
}

#[test]
fn bad_cover_is_refused_naming_the_field_the_limit_and_the_memory() {
    let covered = |table: &str| plus(&format!("[grass.cover]\n{table}"));
    for (table, expected) in [
        (
            "density = -3.0\nview_distance = 50.0",
            "grass.cover.density: -3 is not allowed, use a number above 0",
        ),
        (
            "density = 40.0\nview_distance = nan",
            "grass.cover.view_distance: NaN is not allowed, use a number above 0 and at most 200",
        ),
        (
            "density = 40.0\nview_distance = 500.0",
            "grass.cover.view_distance: 500 is not allowed, use a number above 0 and at most 200",
        ),
        (
            "density = 40.0\nview_distance = 50.0\nsimulate_radius = 60.0",
            "grass.cover.simulate_radius: 60 is not allowed, use a distance in 0..=50 m (the view distance)",
        ),
        (
            "density = 40.0\nview_distance = 50.0\nsimulate_radius = -1.0",
            "grass.cover.simulate_radius: -1 is not allowed",
        ),
        (
            "density = 1000.0\nview_distance = 200.0",
            "grass.cover.view_distance: 200 m at 1000 blades a square metre makes 101 x 101 tiles of 16000 blades, 163216000 blades (20.9 GB of control points), over the 9999990 allowed; lower view_distance or density",
        ),
        (
            "density = 40.0\nview_distance = 50.0\nsize = [1000.0, 0.0]",
            "grass.cover.size[1]: 0 is not allowed, use a number above 0 and at most 100000",
        ),
        (
            "density = 40.0\nview_distance = 50.0\nsize = [1e9, 10.0]",
            "grass.cover.size[0]: 1000000000 is not allowed, use a number above 0 and at most 100000",
        ),
        (
            "density = 40.0\nview_distance = 50.0\nsize = [100.0, 100.0]\ncenter = [inf, 0.0]",
            "grass.cover.center: [inf, 0.0] is not allowed, every value must be a finite number",
        ),
        (
            "density = 40.0\nview_distance = 50.0\ncenter = [10.0, 0.0]",
            "grass.cover.center: is the centre of the cover's rectangle, which has no size; add size = [w, d] (m) or remove center",
        ),
    ] {
        let err = file::parse(&covered(table), "bad.toml")
            .err()
            .unwrap_or_else(|| panic!("{table} was accepted"))
            .to_string();
        assert!(err.contains(expected), "{table}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    // A cover alone is grass enough; its radius defaults to 30 m.
    let alone = MINIMAL.replace(
        "[[grass.bunch]]\ncenter = [0.0, 0.0]\nradius = 0.2\ncount = 10\n",
        "",
    ) + "[grass.cover]\ndensity = 40.0\nview_distance = 60.0\nseed = 3\n";
    let scene = file::parse(&alone, "cover.toml").unwrap_or_else(|e| panic!("{e}"));
    let cover = scene.grass.cover.unwrap();
    assert_eq!(cover.simulate_radius(), 30.0);
    assert_eq!(cover.seed, Some(3));
    // Within a shorter view distance, the default is the view distance.
    let near = alone.replace("view_distance = 60.0", "view_distance = 12.0");
    let scene = file::parse(&near, "cover.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.grass.cover.unwrap().simulate_radius(), 12.0);
    // A kilometre-wide cover centred off the origin.
    let bounded = alone.replace(
        "seed = 3\n",
        "seed = 3\nsize = [1000.0, 200.0]\ncenter = [400.0, -50.0]\n",
    );
    let scene = file::parse(&bounded, "cover.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene.grass.cover.unwrap().bounds(),
        [-100.0, -150.0, 900.0, 50.0]
    );
    // A camera farther from a bounded cover than its view distance sees
    // none of it.
    let far = alone.replace(
        "seed = 3\n",
        "seed = 3\nsize = [100.0, 100.0]\ncenter = [1000.0, 0.0]\n",
    );
    let err = file::parse(&far, "cover.toml").unwrap_err().to_string();
    assert!(
        err.contains("camera.position: is 950 m from the grass.cover's rectangle (x 950..1050, z -50..50), beyond its view_distance of 60 m"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);
}
