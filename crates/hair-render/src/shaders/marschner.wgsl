// Marschner hair shading: the R, TT and TRT lobes of a dielectric cylinder
// (`crate::marschner` is the CPU reference and documents the equations, step for step).

const KAPPA_TT: f32 = 4.0;
const KAPPA_TRT: f32 = 8.0;
const TWO_PI: f32 = 6.283185307;

fn marschner_gaussian(width: f32, x: f32) -> f32 {
    return exp(-x * x / (2.0 * width * width)) / (width * sqrt(TWO_PI));
}

fn marschner_von_mises(kappa: f32, cos_x: f32) -> f32 {
    return exp(kappa * (cos_x - 1.0)) * sqrt(kappa / TWO_PI);
}

fn marschner_fresnel(f0: f32, c: f32) -> f32 {
    let m = 1.0 - clamp(c, 0.0, 1.0);
    return f0 + (1.0 - f0) * m * m * m * m * m;
}

// S·cos θ_i per channel; `params` = (1, shift α_R [rad], width β_R [rad], refractive index).
fn marschner_scatter(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, absorption: vec3<f32>, params: vec4<f32>) -> vec3<f32> {
    let sin_i = clamp(dot(tangent, to_light), -1.0, 1.0);
    let sin_r = clamp(dot(tangent, to_eye), -1.0, 1.0);
    let theta_i = asin(sin_i);
    let theta_r = asin(sin_r);
    let theta_h = 0.5 * (theta_i + theta_r);
    let cos_d = max(cos(0.5 * (theta_r - theta_i)), 1e-3);
    let cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0));
    let light_normal = to_light - sin_i * tangent;
    let eye_normal = to_eye - sin_r * tangent;
    let norms = sqrt(dot(light_normal, light_normal) * dot(eye_normal, eye_normal));
    var cos_phi = 1.0;
    if (norms > 1e-12) {
        cos_phi = clamp(dot(light_normal, eye_normal) / norms, -1.0, 1.0);
    }
    let cos_half_phi = sqrt(max(0.5 + 0.5 * cos_phi, 0.0));

    let shift = params.y;
    let width = params.z;
    let eta = params.w;
    let f0 = ((eta - 1.0) / (eta + 1.0)) * ((eta - 1.0) / (eta + 1.0));
    let m_r = marschner_gaussian(width, theta_h - shift);
    let m_tt = marschner_gaussian(0.5 * width, theta_h + 0.5 * shift);
    let m_trt = marschner_gaussian(2.0 * width, theta_h + 1.5 * shift);

    let n_r = 0.25 * cos_half_phi * marschner_fresnel(f0, cos_d * cos_half_phi);
    let f = marschner_fresnel(f0, cos_d);
    // At least 1e-6: WGSL's pow is undefined at 0.
    let a = clamp(absorption, vec3<f32>(1e-6), vec3<f32>(1.0));
    let n_tt = (1.0 - f) * (1.0 - f) * marschner_von_mises(KAPPA_TT, -cos_phi);
    let n_trt = (1.0 - f) * (1.0 - f) * f * marschner_von_mises(KAPPA_TRT, cos_phi);
    let scatter = vec3<f32>(m_r * n_r)
        + m_tt * n_tt * pow(a, vec3<f32>(1.0 / cos_d))
        + m_trt * n_trt * pow(a, vec3<f32>(2.0 / cos_d));
    return scatter * (cos_i / (cos_d * cos_d));
}
