//! The user's own build of the OMM SDK, loaded at run time from the path in
//! `OMM_SDK_LIB` (the shared library `libomm-lib.so`; see README.md for how
//! to build it), and safe owners of its handles: a baker, a texture, a bake
//! result, each destroyed once when dropped. Nothing of the SDK is compiled
//! into this crate: without `OMM_SDK_LIB` every bake fails with a message
//! saying so.

use std::ffi::{c_char, c_void, CStr};
use std::sync::{Mutex, OnceLock};

use libloading::Library;

use super::ffi;

/// The environment variable naming the compiled SDK library.
pub const ENV: &str = "OMM_SDK_LIB";

/// The SDK's entry points, resolved once per process.
pub struct Sdk {
    // Kept alive for the function pointers below.
    _library: Library,
    get_library_desc: ffi::GetLibraryDesc,
    create_baker: ffi::CreateBaker,
    destroy_baker: ffi::DestroyBaker,
    create_texture: ffi::CreateTexture,
    destroy_texture: ffi::DestroyTexture,
    bake: ffi::Bake,
    destroy_bake_result: ffi::DestroyBakeResult,
    get_bake_result_desc: ffi::GetBakeResultDesc,
}

/// The SDK named by `OMM_SDK_LIB`, loaded on first use (the load is not in
/// any timed bake after the first).
pub fn sdk() -> Result<&'static Sdk, String> {
    static SDK: OnceLock<Result<Sdk, String>> = OnceLock::new();
    SDK.get_or_init(load).as_ref().map_err(Clone::clone)
}

/// Which SDK `OMM_SDK_LIB` loads: `OMM SDK 1.7.1 from PATH`, or why none.
pub fn describe() -> String {
    match sdk() {
        Ok(sdk) => {
            let v = sdk.version();
            let path = std::env::var_os(ENV).unwrap_or_default();
            format!(
                "OMM SDK {}.{}.{} from {}",
                v.major,
                v.minor,
                v.build,
                std::path::Path::new(&path).display()
            )
        }
        Err(e) => e,
    }
}

/// Whether `OMM_SDK_LIB` is set (tests run the SDK only then).
pub fn configured() -> bool {
    std::env::var_os(ENV).is_some()
}

fn load() -> Result<Sdk, String> {
    if !cfg!(any(target_arch = "x86_64", target_arch = "aarch64")) {
        // omm.h declares its functions __fastcall on 32-bit x86.
        return Err("the OMM SDK adapter is declared for x86-64 and AArch64 only".into());
    }
    let path = std::env::var_os(ENV).ok_or_else(|| {
        format!(
            "{ENV} is not set: point it at your own build of the OMM SDK's \
             libomm-lib.so (crates/other-bakers/README.md)"
        )
    })?;
    let shown = std::path::Path::new(&path).display().to_string();
    // SAFETY: loading runs the library's initialisers; the user names their
    // own build of the OMM SDK, whose initialisers are the C++ runtime's.
    let library = unsafe { Library::new(&path) }.map_err(|e| format!("{ENV}={shown}: {e}"))?;
    // SAFETY: each symbol is the SDK function of that name, whose C
    // signature (omm.h 1.7.1) the type in `ffi` declares.
    unsafe {
        macro_rules! symbol {
            ($name:literal) => {
                *library
                    .get(concat!($name, "\0").as_bytes())
                    .map_err(|e| format!("{ENV}={shown}: {}: {e}", $name))?
            };
        }
        let sdk = Sdk {
            get_library_desc: symbol!("ommGetLibraryDesc"),
            create_baker: symbol!("ommCreateBaker"),
            destroy_baker: symbol!("ommDestroyBaker"),
            create_texture: symbol!("ommCpuCreateTexture"),
            destroy_texture: symbol!("ommCpuDestroyTexture"),
            bake: symbol!("ommCpuBake"),
            destroy_bake_result: symbol!("ommCpuDestroyBakeResult"),
            get_bake_result_desc: symbol!("ommCpuGetBakeResultDesc"),
            _library: library,
        };
        let v = sdk.version();
        if (v.major, v.minor) != (1, 7) {
            return Err(format!(
                "{ENV}={shown} is OMM SDK {}.{}.{}; these declarations are for 1.7",
                v.major, v.minor, v.build
            ));
        }
        Ok(sdk)
    }
}

impl Sdk {
    /// `ommGetLibraryDesc`.
    pub fn version(&self) -> ffi::LibraryDesc {
        // SAFETY: no arguments; returns a 3-byte struct by value.
        unsafe { (self.get_library_desc)() }
    }
}

/// The messages the SDK reported through its message callback.
struct Messages(Mutex<Vec<String>>);

/// The SDK's message callback: keeps the text. Never unwinds into C.
unsafe extern "C" fn keep_message(severity: u32, message: *const c_char, user: *mut c_void) {
    if message.is_null() || user.is_null() {
        return;
    }
    // SAFETY: `user` is the `Messages` the baker owns (boxed, outliving the
    // baker handle); `message` is a NUL-terminated string from the SDK.
    let (messages, text) = unsafe { (&*(user as *const Messages), CStr::from_ptr(message)) };
    if let Ok(mut list) = messages.0.lock() {
        list.push(format!("severity {severity}: {}", text.to_string_lossy()));
    }
}

/// An `ommBaker` of type CPU.
pub struct Baker {
    sdk: &'static Sdk,
    handle: ffi::Handle,
    // Boxed: its address is the callback's user argument.
    messages: Box<Messages>,
}

impl Baker {
    /// `ommCreateBaker` with the default allocator and a message callback.
    pub fn new(sdk: &'static Sdk) -> Result<Self, String> {
        let messages = Box::new(Messages(Mutex::new(Vec::new())));
        let desc = ffi::BakerCreationDesc {
            baker_type: ffi::BAKER_TYPE_CPU,
            allocator: ffi::MemoryAllocatorInterface {
                allocate: std::ptr::null(),
                reallocate: std::ptr::null(),
                free: std::ptr::null(),
                user_arg: std::ptr::null_mut(),
            },
            messages: ffi::MessageInterface {
                callback: Some(keep_message),
                user_arg: std::ptr::from_ref::<Messages>(&messages) as *mut c_void,
            },
        };
        let mut handle = std::ptr::null_mut();
        // SAFETY: `desc` is a valid ommBakerCreationDesc for the call; the
        // message box outlives the handle (dropped after it, in `drop`).
        let r = unsafe { (sdk.create_baker)(&desc, &mut handle) };
        let baker = Self {
            sdk,
            handle,
            messages,
        };
        baker.check("ommCreateBaker", r)?;
        Ok(baker)
    }

    /// `Err` naming the call, the result and the SDK's messages, unless `r`
    /// is success.
    fn check(&self, call: &str, r: ffi::OmmResult) -> Result<(), String> {
        if r == ffi::SUCCESS {
            return Ok(());
        }
        let messages = self
            .messages
            .0
            .lock()
            .map(|m| m.join("; "))
            .unwrap_or_default();
        Err(format!("{call}: {} {messages}", ffi::result_name(r)))
    }

    /// `ommCpuCreateTexture`: one mip of tightly packed UNORM8 alpha.
    pub fn texture(
        &self,
        width: u32,
        height: u32,
        alpha: &[u8],
        alpha_cutoff: f32,
    ) -> Result<Texture<'_>, String> {
        if alpha.len() as u64 != u64::from(width) * u64::from(height) {
            return Err(format!(
                "{} alpha bytes for {width} x {height}",
                alpha.len()
            ));
        }
        let mip = ffi::TextureMipDesc {
            width,
            height,
            row_pitch: 0,
            data: alpha.as_ptr().cast(),
        };
        let desc = ffi::TextureDesc {
            format: ffi::TEXTURE_FORMAT_UNORM8,
            flags: 0,
            mips: &mip,
            mip_count: 1,
            alpha_cutoff,
        };
        let mut handle = std::ptr::null_mut();
        // SAFETY: `desc` and `mip` point at `width * height` bytes (checked
        // above); the SDK copies the texels into its own texture.
        let r = unsafe { (self.sdk.create_texture)(self.handle, &desc, &mut handle) };
        self.check("ommCpuCreateTexture", r)?;
        Ok(Texture {
            baker: self,
            handle,
        })
    }

    /// `ommCpuBake` with `desc`, whose `texture` must be one of this
    /// baker's textures and whose buffers outlive the call.
    pub fn bake(&self, desc: &ffi::BakeInputDesc) -> Result<BakeResult<'_>, String> {
        let mut handle = std::ptr::null_mut();
        // SAFETY: the caller's contract above; the SDK reads the buffers
        // only during the call.
        let r = unsafe { (self.sdk.bake)(self.handle, desc, &mut handle) };
        self.check("ommCpuBake", r)?;
        Ok(BakeResult {
            baker: self,
            handle,
        })
    }
}

impl Drop for Baker {
    fn drop(&mut self) {
        if !self.handle.is_null() {
            // SAFETY: created by ommCreateBaker; its textures and results
            // borrow `self`, so they are gone.
            unsafe { (self.sdk.destroy_baker)(self.handle) };
        }
    }
}

/// An `ommCpuTexture`.
pub struct Texture<'a> {
    baker: &'a Baker,
    /// For `BakeInputDesc::texture`.
    pub handle: ffi::Handle,
}

impl Drop for Texture<'_> {
    fn drop(&mut self) {
        // SAFETY: created by this baker's ommCpuCreateTexture.
        unsafe { (self.baker.sdk.destroy_texture)(self.baker.handle, self.handle) };
    }
}

/// An `ommCpuBakeResult`.
pub struct BakeResult<'a> {
    baker: &'a Baker,
    handle: ffi::Handle,
}

/// The result's buffers, borrowed from the SDK.
pub struct ResultView<'r> {
    /// `arrayData`: the packed micromaps.
    pub data: &'r [u8],
    /// `descArray`: one record per micromap.
    pub records: &'r [ffi::MicromapDesc],
    /// `indexBuffer` as i32 (`Force32BitIndices`), one per triangle.
    pub indices: &'r [i32],
}

impl BakeResult<'_> {
    /// `ommCpuGetBakeResultDesc`, its buffers as slices. The index format
    /// must be 32-bit (the bake asks for it).
    pub fn view(&self) -> Result<ResultView<'_>, String> {
        let mut desc: *const ffi::BakeResultDesc = std::ptr::null();
        // SAFETY: a live result handle; the SDK writes a pointer to its
        // own descriptor, valid while the result lives.
        let r = unsafe { (self.baker.sdk.get_bake_result_desc)(self.handle, &mut desc) };
        self.baker.check("ommCpuGetBakeResultDesc", r)?;
        if desc.is_null() {
            return Err("ommCpuGetBakeResultDesc gave no descriptor".into());
        }
        // SAFETY: non-null, owned by the result (borrowed for `'_`).
        let d = unsafe { &*desc };
        if d.index_format != ffi::INDEX_FORMAT_UINT_32 {
            return Err(format!(
                "index format {} (asked for 32-bit)",
                d.index_format
            ));
        }
        // SAFETY: each pointer/count pair is a buffer of the result, valid
        // while it lives; a zero count may come with a null pointer.
        unsafe {
            Ok(ResultView {
                data: slice(d.array_data.cast::<u8>(), d.array_data_size),
                records: slice(d.desc_array, d.desc_array_count),
                indices: slice(d.index_buffer.cast::<i32>(), d.index_count),
            })
        }
    }
}

/// `count` elements at `ptr` (empty when `count` is 0, whatever `ptr`).
///
/// # Safety
/// When `count > 0`, `ptr` points at `count` initialised, aligned elements
/// that live for `'a`.
unsafe fn slice<'a, T>(ptr: *const T, count: u32) -> &'a [T] {
    if count == 0 || ptr.is_null() {
        return &[];
    }
    // SAFETY: the caller's contract.
    unsafe { std::slice::from_raw_parts(ptr, count as usize) }
}

impl Drop for BakeResult<'_> {
    fn drop(&mut self) {
        // SAFETY: created by ommCpuBake; views borrow `self`, so are gone.
        unsafe { (self.baker.sdk.destroy_bake_result)(self.handle) };
    }
}
