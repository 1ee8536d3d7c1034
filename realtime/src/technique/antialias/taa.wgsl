// Temporal anti-aliasing (Karis 2014, "High-Quality Temporal Supersampling", SIGGRAPH course
// "Advances in Real-Time Rendering"). Each frame samples every pixel once, at a sub-pixel
// offset that follows the Halton (2, 3) sequence (taa.rs), and this pass blends it into the
// history, the previous output reprojected to this frame:
//   history ← (1 − blend) · clip(history at the pixel's previous position) + blend · frame.
// Reprojection follows the surface at the pixel's depth (the normal + depth target) back into
// the previous camera, or the direction for the background; the history is read bilinearly,
// which blurs it a little each frame the view moves. Objects that move on their own would need
// motion vectors; the studies move only the camera. Where the previous view saw something
// else (a disocclusion), the history is wrong: `clamp` limits it to the new frame's 3×3
// neighbourhood (its RGB box, or Karis's clip towards the centre of its YCoCg box), which
// trades that ghosting for flicker of sub-pixel detail. A history from outside the previous
// image, and the first frame, start from the frame alone. On a still view with jitter the
// blend converges to a weighted mean of jittered samples: the pixel's box filter, at
// 1/blend-ish effective samples.
// post.p0 = (blend, first frame (1) or not (0), clamp: 0 none, 1 aabb, 2 clip, 0).

fn camera_ray(x: vec2<f32>) -> vec3<f32> {
    // Camera::ray_direction for film position x (docs/ARCHITECTURE.md "Camera").
    let xc = (2.0 * x.x / post.film.x - 1.0) * post.film.z * post.film.w;
    let yc = (1.0 - 2.0 * x.y / post.film.y) * post.film.z;
    return normalize(post.cam_x.xyz * xc + post.cam_y.xyz * yc - post.cam_z.xyz);
}

fn rgb_to_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        0.25 * c.r + 0.5 * c.g + 0.25 * c.b,
        0.5 * c.r - 0.5 * c.b,
        -0.25 * c.r + 0.5 * c.g - 0.25 * c.b,
    );
}

fn ycocg_to_rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// h moved along the line to the box's centre until it lies inside the box [lo, hi].
fn clip_to_box(lo: vec3<f32>, hi: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let centre = 0.5 * (hi + lo);
    let extent = 0.5 * (hi - lo) + vec3<f32>(1e-6);
    let v = h - centre;
    let a = abs(v / extent);
    let m = max(a.x, max(a.y, a.z));
    return select(h, centre + v / m, m > 1.0);
}

fn taa_pixel(frag: vec4<f32>) -> vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let current = load_clamped(src, p);
    if post.p0.y > 0.5 {
        return current;
    }
    // Where this pixel's surface was in the previous frame.
    let film_x = frag.xy * post.film.xy * post.size.zw;
    let dir = camera_ray(film_x);
    let depth = load_clamped(aux, p).w;
    var clip: vec4<f32>;
    if depth > 0.0 {
        let world = post.cam_pos.xyz + dir * (depth / dot(dir, post.cam_forward.xyz));
        clip = post.prev_view_proj * vec4<f32>(world, 1.0);
    } else {
        clip = post.prev_view_proj * vec4<f32>(dir, 0.0);
    }
    if clip.w <= 0.0 {
        return current;
    }
    let ndc = clip.xy / clip.w;
    let previous = vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y) * post.size.xy;
    if any(previous < vec2<f32>(0.0)) || any(previous > post.size.xy) {
        return current;
    }
    var h = bilinear(history, previous).rgb;
    let mode = u32(post.p0.z);
    if mode != 0u {
        var lo = vec3<f32>(1e30);
        var hi = vec3<f32>(-1e30);
        for (var dy = -1; dy <= 1; dy += 1) {
            for (var dx = -1; dx <= 1; dx += 1) {
                var c = load_clamped(src, p + vec2<i32>(dx, dy)).rgb;
                if mode == 2u {
                    c = rgb_to_ycocg(c);
                }
                lo = min(lo, c);
                hi = max(hi, c);
            }
        }
        if mode == 1u {
            h = clamp(h, lo, hi);
        } else {
            h = ycocg_to_rgb(clip_to_box(lo, hi, rgb_to_ycocg(h)));
        }
    }
    return vec4<f32>(mix(h, current.rgb, post.p0.x), current.a);
}

@fragment
fn fs_taa(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let out = taa_pixel(frag);
    flush_taps(frag.y);
    return out;
}
