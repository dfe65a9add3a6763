// One sample of a chain's curve frame at u = i / along_segments: the chain's B-spline C(u) and the
// B-splines N(u), B(u) of its node normals and binormals, with their derivatives d/du. Because a
// B-spline is linear in its control points, a strand at root offset o is exactly
// C(u) + o.x·N(u) + o.y·B(u), with tangent C'(u) + o.x·N'(u) + o.y·B'(u): the evaluation is done
// once per chain sample instead of once per strand vertex.
struct ChainSample {
    position: vec4<f32>,
    normal: vec4<f32>,
    binormal: vec4<f32>,
    d_position: vec4<f32>,
    d_normal: vec4<f32>,
    d_binormal: vec4<f32>,
}
