// The bindings of FXAA, MLAA and TAA (technique/antialias/post.rs): the image being
// anti-aliased, two more inputs that depend on the pass, and the pass's parameters.

struct PostParams {
    // Target width, height, 1/width, 1/height.
    size: vec4<f32>,
    // The method's parameters (post.rs `post_params` names each).
    p0: vec4<f32>,
    p1: vec4<f32>,
    // TAA: the previous frame's view-projection (without its jitter) and this frame's camera,
    // as in FrameUniforms.
    prev_view_proj: mat4x4<f32>,
    cam_pos: vec4<f32>,
    cam_x: vec4<f32>,
    cam_y: vec4<f32>,
    cam_z: vec4<f32>,
    cam_forward: vec4<f32>,
    // Final film width, height, tan(fov_y/2), aspect W/H.
    film: vec4<f32>,
}

// The lit image (the colour target).
@group(0) @binding(0) var src: texture_2d<f32>;
// MLAA: the edges (weights pass) or the blend weights (blend pass); TAA: normal + view depth.
@group(0) @binding(1) var aux: texture_2d<f32>;
// TAA: the history.
@group(0) @binding(2) var history: texture_2d<f32>;
@group(0) @binding(3) var<uniform> post: PostParams;
