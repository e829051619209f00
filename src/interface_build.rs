//! The build-time half of the Rust/GLSL interface: reads
//! src/interface/defs.rs (the one source of every push-constant block,
//! shared struct and constant both sides use) and writes its GLSL
//! (`interface.glsl`, which shaders `#include`) and, for the library, a
//! compile-time check that each Rust field lies where std430 puts the
//! GLSL member, plus a table of the layouts for the reflection tests.
//! Not a module of the library: build.rs includes it with `#[path]`.

use std::collections::BTreeMap;
use std::fmt::Write as _;

/// One item of the definitions, as the build's `gpu_interface!` records it.
pub enum Item {
    Const {
        name: &'static str,
        ty: &'static str,
        /// The value as Rust's `{:?}` prints it.
        value: String,
        docs: &'static [&'static str],
    },
    Struct {
        name: &'static str,
        docs: &'static [&'static str],
        fields: Vec<Field>,
    },
}

pub struct Field {
    pub name: &'static str,
    /// The Rust type as `stringify!` wrote it.
    pub ty: &'static str,
    pub docs: &'static [&'static str],
}

/// Records the definitions into `$items` instead of defining them: the
/// build's reading of src/interface/defs.rs. Each constant is also defined
/// here so that a later one may be computed from it.
macro_rules! gpu_interface_record {
    ($items:ident;) => {};
    ($items:ident; $(#[doc = $doc:literal])* pub const $name:ident : $ty:ty = $value:expr; $($rest:tt)*) => {{
        #[allow(dead_code)]
        const $name: $ty = $value;
        $items.push($crate::interface_build::Item::Const {
            name: stringify!($name),
            ty: stringify!($ty),
            value: format!("{:?}", $name),
            docs: &[$($doc),*],
        });
        gpu_interface_record! { $items; $($rest)* }
    }};
    ($items:ident; $(#[doc = $doc:literal])* pub struct $name:ident {
        $($(#[doc = $fdoc:literal])* pub $field:ident : $fty:ty),* $(,)?
    } $($rest:tt)*) => {{
        $items.push($crate::interface_build::Item::Struct {
            name: stringify!($name),
            docs: &[$($doc),*],
            fields: vec![$($crate::interface_build::Field {
                name: stringify!($field),
                ty: stringify!($fty),
                docs: &[$($fdoc),*],
            }),*],
        });
        gpu_interface_record! { $items; $($rest)* }
    }};
}

/// A GLSL type and its std430 size and alignment.
#[derive(Clone)]
struct Glsl {
    /// The type's name (`vec4`, `WindGridParams`).
    name: String,
    /// The array suffix after the member's name (`[MAX_PATH_POINTS]`), if any.
    array: String,
    size: u32,
    align: u32,
}

fn round_up(x: u32, to: u32) -> u32 {
    x.div_ceil(to) * to
}

fn scalar(ty: &str) -> Option<&'static str> {
    match ty {
        "f32" => Some("float"),
        "u32" => Some("uint"),
        "i32" => Some("int"),
        _ => None,
    }
}

/// `[X;N]` (spaces removed) as (X, N), split at the outer `;`.
fn split_array(ty: &str) -> Option<(&str, &str)> {
    let inner = ty.strip_prefix('[')?.strip_suffix(']')?;
    let mut depth = 0;
    let mut at = None;
    for (i, c) in inner.char_indices() {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            ';' if depth == 0 => at = Some(i),
            _ => {}
        }
    }
    let at = at?;
    Some((&inner[..at], &inner[at + 1..]))
}

/// The GLSL of a Rust field type: f32, u32, i32; `[T; 2..4]` of those as
/// vectors (vec3 aligned to 16, as std430 has it); `Mat4Columns` as mat4;
/// `[T; N]` of anything else as an array (N a number or a constant defined
/// above); a struct defined above by its name.
fn glsl_type(
    ty: &str,
    structs: &BTreeMap<String, Glsl>,
    consts: &BTreeMap<String, String>,
) -> Result<Glsl, String> {
    let ty: String = ty.chars().filter(|c| !c.is_whitespace()).collect();
    if let Some(s) = scalar(&ty) {
        return Ok(Glsl {
            name: s.into(),
            array: String::new(),
            size: 4,
            align: 4,
        });
    }
    if ty == "Mat4Columns" {
        return Ok(Glsl {
            name: "mat4".into(),
            array: String::new(),
            size: 64,
            align: 16,
        });
    }
    if let Some((elem, len)) = split_array(&ty) {
        let count: u32 = match len.parse() {
            Ok(n) => n,
            Err(_) => consts
                .get(len)
                .and_then(|v| v.parse().ok())
                .ok_or_else(|| {
                    format!("array length `{len}` is no number nor constant defined above")
                })?,
        };
        if let (Some(s), 2..=4) = (scalar(elem), count) {
            let prefix = &s[..1];
            let name = match prefix {
                "f" => format!("vec{count}"),
                p => format!("{p}vec{count}"),
            };
            return Ok(Glsl {
                name,
                array: String::new(),
                size: 4 * count,
                align: if count == 2 { 8 } else { 16 },
            });
        }
        let e = glsl_type(elem, structs, consts)?;
        if !e.array.is_empty() {
            return Err(format!("`{ty}`: arrays of arrays are not supported"));
        }
        let stride = round_up(e.size, e.align);
        return Ok(Glsl {
            name: e.name,
            array: format!("[{len}]"),
            size: stride * count,
            align: e.align,
        });
    }
    structs
        .get(&ty)
        .cloned()
        .ok_or_else(|| format!("type `{ty}` is not f32, u32, i32, an array of them, Mat4Columns or a struct defined above"))
}

/// The generated files' text: the GLSL header and the Rust layout checks.
pub struct Generated {
    pub glsl: String,
    pub rust: String,
}

fn comment(out: &mut String, indent: &str, docs: &[&str]) {
    for d in docs {
        writeln!(out, "{indent}//{}", d.trim_end()).unwrap();
    }
}

/// Push-constant blocks (structs named `...Push`) must fit the 128 bytes
/// every Vulkan device offers (maxPushConstantsSize's minimum).
const MAX_PUSH_BYTES: u32 = 128;

/// The three texts being written: the GLSL, the Rust checks, the table.
struct Out {
    glsl: String,
    rust: String,
    table: String,
}

pub fn generate(items: &[Item]) -> Result<Generated, String> {
    let mut out = Out {
        glsl: String::from(
            "// Generated by build.rs from src/interface/defs.rs: edit that file, not this one.\n\
             #ifndef MEADOW_INTERFACE_GLSL\n#define MEADOW_INTERFACE_GLSL\n\n",
        ),
        rust: String::from(
            "// Generated by build.rs from src/interface/defs.rs: each field where std430 puts it.\n\n",
        ),
        table: String::from(
            "/// Every struct of src/interface/defs.rs: its name, Rust size and each field's Rust offset.\n\
             pub const LAYOUTS: &[StructLayout] = &[\n",
        ),
    };
    let mut structs: BTreeMap<String, Glsl> = BTreeMap::new();
    let mut consts: BTreeMap<String, String> = BTreeMap::new();
    for item in items {
        match item {
            Item::Const {
                name,
                ty,
                value,
                docs,
            } => {
                let literal = match *ty {
                    "u32" => format!("{value}u"),
                    "i32" | "usize" => value.clone(),
                    "f32" if value.contains(['.', 'e', 'E']) => value.clone(),
                    "f32" => format!("{value}.0"),
                    other => return Err(format!("constant {name}: type {other} has no GLSL form")),
                };
                comment(&mut out.glsl, "", docs);
                writeln!(out.glsl, "#define {name} {literal}\n").unwrap();
                consts.insert(name.to_string(), value.clone());
            }
            Item::Struct { name, docs, fields } => {
                let layout = write_struct(name, docs, fields, &structs, &consts, &mut out)?;
                structs.insert(name.to_string(), layout);
            }
        }
    }
    out.glsl.push_str("#endif\n");
    out.table.push_str("];\n");
    out.rust.push('\n');
    out.rust.push_str(&out.table);
    Ok(Generated {
        glsl: out.glsl,
        rust: out.rust,
    })
}

/// Writes one struct's GLSL, its Rust layout checks and its table entry;
/// returns its std430 layout for the structs after it.
fn write_struct(
    name: &str,
    docs: &[&str],
    fields: &[Field],
    structs: &BTreeMap<String, Glsl>,
    consts: &BTreeMap<String, String>,
    out: &mut Out,
) -> Result<Glsl, String> {
    let Out { glsl, rust, table } = out;
    comment(glsl, "", docs);
    writeln!(glsl, "struct {name} {{").unwrap();
    writeln!(
        table,
        "    StructLayout {{ name: \"{name}\", size: ::core::mem::size_of::<{name}>(), fields: &["
    )
    .unwrap();
    let mut offset = 0;
    let mut align = 4;
    for f in fields {
        let t = glsl_type(f.ty, structs, consts).map_err(|e| format!("{name}.{}: {e}", f.name))?;
        offset = round_up(offset, t.align);
        align = align.max(t.align);
        comment(glsl, "    ", f.docs);
        writeln!(glsl, "    {} {}{};", t.name, f.name, t.array).unwrap();
        writeln!(
            rust,
            "const _: () = assert!(::core::mem::offset_of!({name}, {field}) == {offset}, \
             \"{name}.{field}: std430 puts it at byte {offset}; reorder or pad the fields in src/interface/defs.rs\");",
            field = f.name
        )
        .unwrap();
        writeln!(
            table,
            "        (\"{field}\", ::core::mem::offset_of!({name}, {field})),",
            field = f.name
        )
        .unwrap();
        offset += t.size;
    }
    let size = round_up(offset, align);
    writeln!(glsl, "}};\n").unwrap();
    writeln!(table, "    ] }},").unwrap();
    writeln!(
        rust,
        "const _: () = assert!(::core::mem::size_of::<{name}>() == {size}, \
         \"{name}: std430 makes it {size} bytes; pad the end in src/interface/defs.rs\");"
    )
    .unwrap();
    if name.ends_with("Push") && size > MAX_PUSH_BYTES {
        return Err(format!(
            "{name}: {size} bytes of push constants, more than the {MAX_PUSH_BYTES} every device offers"
        ));
    }
    Ok(Glsl {
        name: name.to_string(),
        array: String::new(),
        size,
        align,
    })
}
