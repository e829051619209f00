//! The Rust/GLSL interface, written once (src/interface/defs.rs): the
//! push-constant blocks of every kernel and pipeline, as `#[repr(C)]`
//! structs with named fields, and the constants both sides use. build.rs
//! writes the same definitions as GLSL (`interface.glsl`, which the
//! shaders include) and checks at compile time that every field lies where
//! std430 puts it, so the two sides cannot disagree: a field renamed or
//! removed fails the shader's compilation, one misplaced fails the
//! library's.

/// The library's reading of src/interface/defs.rs: each struct as a
/// `#[repr(C)]` plain-old-data struct, each constant as itself.
macro_rules! gpu_interface {
    () => {};
    ($(#[doc = $doc:literal])* pub const $name:ident : $ty:ty = $value:expr; $($rest:tt)*) => {
        $(#[doc = $doc])*
        pub const $name: $ty = $value;
        gpu_interface! { $($rest)* }
    };
    ($(#[doc = $doc:literal])* pub struct $name:ident {
        $($(#[doc = $fdoc:literal])* pub $field:ident : $fty:ty),* $(,)?
    } $($rest:tt)*) => {
        $(#[doc = $doc])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $($(#[doc = $fdoc])* pub $field: $fty,)*
        }
        impl Default for $name {
            fn default() -> Self {
                bytemuck::Zeroable::zeroed()
            }
        }
        gpu_interface! { $($rest)* }
    };
}

/// A mat4 as GLSL holds it: four columns (glam's `to_cols_array_2d`).
pub type Mat4Columns = [[f32; 4]; 4];

include!("defs.rs");

/// One struct of the interface as Rust lays it out (for the reflection
/// tests, which compare it with each shader's reading).
#[derive(Clone, Copy, Debug)]
pub struct StructLayout {
    pub name: &'static str,
    pub size: usize,
    /// Each field's name and byte offset, in order.
    pub fields: &'static [(&'static str, usize)],
}

include!(concat!(env!("OUT_DIR"), "/interface_layout.rs"));
