#include "python/gpu_session.h"

#include <mutex>

namespace cvc_python {

std::shared_ptr<engine::GpuContext> sharedContext() {
    static std::mutex mutex;
    static std::weak_ptr<engine::GpuContext> shared;
    // Strong references live in the volumes that rendered: the device goes when the last goes,
    // before the interpreter's own teardown, and the next render makes it again.
    const std::lock_guard<std::mutex> lock(mutex);
    std::shared_ptr<engine::GpuContext> context = shared.lock();
    if (!context) {
        context = std::make_shared<engine::GpuContext>(engine::GpuContextOptions{});
        shared = context;
    }
    return context;
}

SessionVolume::SessionVolume(volumes::LoadedVolume loaded, std::string source)
    : mLoaded(std::move(loaded)), mSource(std::move(source)) {}

SessionVolume::~SessionVolume() {
    mRaycaster.reset();
    mTexture.reset();
    mContext.reset();
}

engine::Raycaster& SessionVolume::raycaster() {
    if (!mRaycaster) {
        mContext = sharedContext();
        mTexture = std::make_unique<engine::VolumeTexture>(*mContext, mLoaded.volume);
        mRaycaster = std::make_unique<engine::Raycaster>(*mContext, mLoaded.volume, *mTexture, mLoaded.bricks);
    }
    return *mRaycaster;
}

}  // namespace cvc_python
