//! (f) With no Vulkan driver visible, asking for Vulkan fails with an error that says what to install.
//! The drivers are hidden from a child process: the test re-runs this test binary with the Vulkan
//! loader's driver lists pointing at a file that does not exist, and the child asks for Vulkan.

use std::process::Command;

/// Set in the child run, which asks for Vulkan with the drivers hidden.
const CHILD_MARKER: &str = "HAIRLOD_CHILD";
/// Printed by the child once its checks passed, so that a child which ran no test cannot pass.
const CHILD_PASSED: &str = "hairlod child: checks passed";
/// A Vulkan driver list (ICD manifest) that does not exist.
const NO_DRIVERS: &str = "/nonexistent/hair-render-icd.json";

#[test]
fn missing_vulkan_driver_error_says_what_to_install() {
    if std::env::var_os(CHILD_MARKER).is_some() {
        check_vulkan_request_fails();
        println!("{CHILD_PASSED}");
        return;
    }
    let output = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "missing_vulkan_driver_error_says_what_to_install",
            "--nocapture",
        ])
        .env(CHILD_MARKER, "1")
        .env("VK_ICD_FILENAMES", NO_DRIVERS)
        .env("VK_DRIVER_FILES", NO_DRIVERS)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success() && stdout.contains(CHILD_PASSED),
        "the child run did not pass ({}):\n{stdout}\n{stderr}",
        output.status
    );
}

/// In the child, where no Vulkan driver is visible: asking for Vulkan gives `NoAdapter`, whose
/// message names the backend and the packages to install.
fn check_vulkan_request_fails() {
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
