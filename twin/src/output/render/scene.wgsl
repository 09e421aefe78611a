// Shaders of the headless renderer (see render.rs for the conventions).
// World: Z-up, right-handed, metres. Colours arrive in linear RGB; the
// render target is sRGB so the hardware encodes on write.

struct Globals {
    clip_from_world: mat4x4<f32>,
    // xyz: camera eye in world (m).
    eye_in_world: vec4<f32>,
    // xyz: unit vector from surfaces towards the key light.
    to_light_in_world: vec4<f32>,
    // x: grid fade start (m from eye), y: fade end, z/w: grid centre x/y (m).
    grid: vec4<f32>,
    // x/y: image size (px), z: trail line width (px).
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

// ---------------------------------------------------------------- meshes

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // world_from_mesh, columns.
    @location(2) m0: vec4<f32>,
    @location(3) m1: vec4<f32>,
    @location(4) m2: vec4<f32>,
    @location(5) m3: vec4<f32>,
    // Normal matrix (inverse transpose of the linear part, up to a positive
    // factor), columns; n0.w is -1 for mirroring transforms, +1 otherwise.
    @location(6) n0: vec4<f32>,
    @location(7) n1: vec4<f32>,
    @location(8) n2: vec4<f32>,
    // Linear RGBA after the tint is applied.
    @location(9) color: vec4<f32>,
};

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) @interpolate(flat) mirror: f32,
};

@vertex
fn vs_mesh(in: MeshIn) -> MeshOut {
    let world_from_mesh = mat4x4<f32>(in.m0, in.m1, in.m2, in.m3);
    let normal_matrix = mat3x3<f32>(in.n0.xyz, in.n1.xyz, in.n2.xyz);
    let world = world_from_mesh * vec4<f32>(in.position, 1.0);
    var out: MeshOut;
    out.clip = globals.clip_from_world * world;
    out.world = world.xyz;
    out.normal = normal_matrix * in.normal;
    out.color = in.color;
    out.mirror = in.n0.w;
    return out;
}

@fragment
fn fs_mesh(in: MeshOut, @builtin(front_facing) front_facing: bool) -> @location(0) vec4<f32> {
    let to_eye = normalize(globals.eye_in_world.xyz - in.world);
    var n = in.normal;
    let len = length(n);
    if (len > 1e-20) {
        n = n / len;
    } else {
        n = to_eye;
    }
    // Counter-clockwise triangles are the outside; a mirroring transform
    // turns them clockwise. Seen from inside, light the inner surface.
    let outside = front_facing != (in.mirror < 0.0);
    if (!outside) {
        n = -n;
    }
    let l = globals.to_light_in_world.xyz;
    // Hemisphere ambient: brighter from the sky (+Z) than from the floor.
    let ambient = mix(0.18, 0.34, 0.5 + 0.5 * n.z);
    let diffuse = 0.78 * max(dot(n, l), 0.0);
    let h = normalize(l + to_eye);
    let specular = 0.12 * pow(max(dot(n, h), 0.0), 40.0) * step(0.0, dot(n, l));
    let rgb = in.color.rgb * (ambient + diffuse) + vec3<f32>(specular);
    return vec4<f32>(rgb, in.color.a);
}

// ------------------------------------------------------------------ grid

struct GridOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_xy: vec2<f32>,
};

@vertex
fn vs_grid(@builtin(vertex_index) index: u32) -> GridOut {
    // Two triangles covering a square of half-width `fade end` on z = 0.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let xy = globals.grid.zw + corners[index] * globals.grid.y;
    var out: GridOut;
    out.clip = globals.clip_from_world * vec4<f32>(xy, 0.0, 1.0);
    out.world_xy = xy;
    return out;
}

// Coverage (0..1) of grid lines `spacing` metres apart, `width_px` wide,
// anti-aliased with screen-space derivatives; also fades lines out where
// they crowd closer than a few pixels.
fn grid_coverage(xy: vec2<f32>, spacing: f32, width_px: f32) -> f32 {
    let c = xy / spacing;
    let d = max(fwidth(c), vec2<f32>(1e-6));
    let dist_px = abs(fract(c - 0.5) - 0.5) / d;
    let line = clamp(0.5 * width_px + 0.5 - min(dist_px.x, dist_px.y), 0.0, 1.0);
    let gap_px = 1.0 / max(d.x, d.y);
    return line * clamp((gap_px - 2.0) / 6.0, 0.0, 1.0);
}

@fragment
fn fs_grid(in: GridOut) -> @location(0) vec4<f32> {
    let xy = in.world_xy;
    let minor = grid_coverage(xy, 0.1, 1.0);
    let major = grid_coverage(xy, 1.0, 1.6);
    // The world axes: X in red (along y = 0), Y in green (along x = 0).
    let axis_d = max(fwidth(xy), vec2<f32>(1e-6));
    let axis_px = abs(xy) / axis_d;
    let x_axis = clamp(1.5 - axis_px.y, 0.0, 1.0);
    let y_axis = clamp(1.5 - axis_px.x, 0.0, 1.0);

    let dist = length(vec3<f32>(xy, 0.0) - globals.eye_in_world.xyz);
    let fade = 1.0 - smoothstep(globals.grid.x, globals.grid.y, dist);

    var rgb = vec3<f32>(0.08, 0.08, 0.09);
    var alpha = max(0.35 * minor, 0.6 * major);
    if (x_axis > 0.0) {
        rgb = mix(rgb, vec3<f32>(0.55, 0.05, 0.04), x_axis);
        alpha = max(alpha, 0.8 * x_axis);
    }
    if (y_axis > 0.0) {
        rgb = mix(rgb, vec3<f32>(0.04, 0.40, 0.06), y_axis);
        alpha = max(alpha, 0.8 * y_axis);
    }
    alpha = alpha * fade;
    if (alpha < 0.002) {
        discard;
    }
    return vec4<f32>(rgb, alpha);
}

// ----------------------------------------------------------------- lines

// Each segment is one instance, expanded to a screen-aligned quad of
// constant pixel width (plain Vulkan lines are one pixel thin and faint
// under MSAA). Segments reaching behind the near plane are dropped.
struct SegmentIn {
    @location(0) start: vec3<f32>,
    @location(1) end: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_line(@builtin(vertex_index) index: u32, in: SegmentIn) -> LineOut {
    // (along, across) for two triangles.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    let corner = corners[index];
    let a = globals.clip_from_world * vec4<f32>(in.start, 1.0);
    let b = globals.clip_from_world * vec4<f32>(in.end, 1.0);
    var out: LineOut;
    out.color = in.color;
    if (a.w <= 0.01 || b.w <= 0.01) {
        // Degenerate triangle: nothing is rasterised.
        out.clip = vec4<f32>(0.0, 0.0, 0.0, 1.0);
        return out;
    }
    let half_size = 0.5 * globals.viewport.xy;
    let pa = a.xy / a.w * half_size;
    let pb = b.xy / b.w * half_size;
    let d = pb - pa;
    let len = length(d);
    var dir = vec2<f32>(1.0, 0.0);
    if (len > 1e-6) {
        dir = d / len;
    }
    let normal = vec2<f32>(-dir.y, dir.x);
    // Extend by half a width at both ends so consecutive segments join.
    let half_width = 0.5 * globals.viewport.z;
    let offset_px = normal * corner.y * half_width + dir * (corner.x * 2.0 - 1.0) * half_width;
    var p = a;
    if (corner.x > 0.5) {
        p = b;
    }
    out.clip = vec4<f32>(p.xy + offset_px / half_size * p.w, p.z, p.w);
    return out;
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.color;
}
