//! The directives of a pbrt-v4 file.

use super::params::ParamList;

/// Which of the two transforms of a motion-blurred scene the transform
/// directives change (`ActiveTransform`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ActiveTransform {
    /// `ActiveTransform StartTime`
    Start,
    /// `ActiveTransform EndTime`
    End,
    /// `ActiveTransform All` (the default)
    All,
}

/// One directive with its arguments, as written; `Include` and `Import`
/// never appear (the parser expands them).
#[derive(Clone, Debug, PartialEq)]
pub enum Directive {
    /// `Camera "type" params`
    Camera(String, ParamList),
    /// `Film "type" params`
    Film(String, ParamList),
    /// `Sampler "type" params`
    Sampler(String, ParamList),
    /// `PixelFilter "type" params`
    PixelFilter(String, ParamList),
    /// `Integrator "type" params`
    Integrator(String, ParamList),
    /// `Accelerator "type" params`
    Accelerator(String, ParamList),
    /// `ColorSpace "name"`
    ColorSpace(String),
    /// `Option "type name" value`: one parameter.
    Option(ParamList),
    /// `WorldBegin`
    WorldBegin,
    /// `AttributeBegin`
    AttributeBegin,
    /// `AttributeEnd`
    AttributeEnd,
    /// `Attribute "target" params`: target is `shape`, `light`,
    /// `material`, `medium` or `texture`.
    Attribute(String, ParamList),
    /// `TransformBegin` (deprecated in pbrt-v4 but accepted)
    TransformBegin,
    /// `TransformEnd`
    TransformEnd,
    /// `Identity`
    Identity,
    /// `Translate x y z`
    Translate([f32; 3]),
    /// `Scale x y z`
    Scale([f32; 3]),
    /// `Rotate angle x y z` (degrees)
    Rotate(f32, [f32; 3]),
    /// `LookAt eye look up`
    LookAt([f32; 9]),
    /// `Transform [ m00 .. m33 ]`: 16 numbers, column-major as pbrt reads
    /// them (the translation is in elements 12–14).
    Transform([f32; 16]),
    /// `ConcatTransform [ 16 numbers ]`
    ConcatTransform([f32; 16]),
    /// `CoordinateSystem "name"`
    CoordinateSystem(String),
    /// `CoordSysTransform "name"`
    CoordSysTransform(String),
    /// `ActiveTransform StartTime|EndTime|All`
    ActiveTransform(ActiveTransform),
    /// `TransformTimes start end`
    TransformTimes(f32, f32),
    /// `ReverseOrientation`
    ReverseOrientation,
    /// `Shape "type" params`
    Shape(String, ParamList),
    /// `Material "type" params`
    Material(String, ParamList),
    /// `MakeNamedMaterial "name" params` (the type is the `string type`
    /// parameter)
    MakeNamedMaterial(String, ParamList),
    /// `NamedMaterial "name"`
    NamedMaterial(String),
    /// `Texture "name" "float"|"spectrum" "class" params`
    Texture {
        /// The texture's name.
        name: String,
        /// `float` or `spectrum` (pbrt-v3's `color` is read as `spectrum`).
        value_type: String,
        /// The texture class (`imagemap`, `checkerboard`, ...).
        class: String,
        /// Its parameters.
        params: ParamList,
    },
    /// `LightSource "type" params`
    LightSource(String, ParamList),
    /// `AreaLightSource "type" params`
    AreaLightSource(String, ParamList),
    /// `MakeNamedMedium "name" params`
    MakeNamedMedium(String, ParamList),
    /// `MediumInterface "inside" "outside"` (one name: both the same)
    MediumInterface(String, String),
    /// `ObjectBegin "name"`
    ObjectBegin(String),
    /// `ObjectEnd`
    ObjectEnd,
    /// `ObjectInstance "name"`
    ObjectInstance(String),
}
