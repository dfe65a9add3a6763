//! (f) With no Vulkan driver visible, asking for Vulkan fails with an error that says what to install.
//! Its own test binary: it hides the Vulkan drivers from this whole process.

#[test]
#[allow(unsafe_code)] // `set_var`, see the SAFETY note below.
fn missing_vulkan_driver_error_says_what_to_install() {
    // SAFETY: this binary runs this single test, before any other thread reads the environment.
    unsafe {
        std::env::set_var("VK_ICD_FILENAMES", "/nonexistent/hair-render-icd.json");
        std::env::set_var("VK_DRIVER_FILES", "/nonexistent/hair-render-icd.json");
    }
    let options = hair_render::RendererOptions {
        device: hair_render::DeviceOptions {
            backend: hair_render::BackendChoice::Vulkan,
            ..Default::default()
        },
    };
    let error = hair_render::Renderer::new(&options).expect_err("no Vulkan driver is visible");
    let message = error.to_string();
    assert!(
        matches!(error, hair_render::RenderError::NoAdapter { .. }),
        "{message}"
    );
    assert!(message.contains("vulkan"), "{message}");
    assert!(message.contains("mesa-vulkan-drivers"), "{message}");
    assert!(message.contains("libgl1-mesa-dri"), "{message}");
}

#[test]
fn unknown_backend_names_are_refused() {
    let error = "metal".parse::<hair_render::BackendChoice>().unwrap_err();
    assert!(
        error
            .to_string()
            .contains("expected `vulkan`, `gl` or `auto`")
    );
}
