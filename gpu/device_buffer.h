// RAII device memory. Allocation failure reports the bytes and what they were for.
#pragma once

#include <cstddef>
#include <vector>

#include "gpu/cuda_check.h"

namespace oct {

template <class T>
class DeviceBuffer {
public:
    DeviceBuffer() = default;
    DeviceBuffer(size_t count, const char* what) { allocate(count, what); }
    ~DeviceBuffer() { release(); }
    DeviceBuffer(const DeviceBuffer&) = delete;
    DeviceBuffer& operator=(const DeviceBuffer&) = delete;
    DeviceBuffer(DeviceBuffer&& o) noexcept : ptr_(o.ptr_), count_(o.count_) {
        o.ptr_ = nullptr;
        o.count_ = 0;
    }

    void allocate(size_t count, const char* what) {
        release();
        if (count == 0) return;
        cudaError_t e = cudaMalloc(reinterpret_cast<void**>(&ptr_), count * sizeof(T));
        if (e != cudaSuccess) {
            ptr_ = nullptr;
            throw CudaError(std::string("cannot allocate ") + std::to_string(count * sizeof(T)) +
                            " bytes of device memory for " + what + ": " + cudaGetErrorName(e) +
                            " (use a smaller scene or --max-depth)");
        }
        count_ = count;
    }
    void upload(const T* host, size_t count, const char* what) {
        allocate(count, what);
        if (count)
            OCT_CUDA_CHECK(cudaMemcpy(ptr_, host, count * sizeof(T), cudaMemcpyHostToDevice));
    }
    void upload(const std::vector<T>& host, const char* what) {
        upload(host.data(), host.size(), what);
    }
    void download(T* host, size_t count) const {
        if (count)
            OCT_CUDA_CHECK(cudaMemcpy(host, ptr_, count * sizeof(T), cudaMemcpyDeviceToHost));
    }
    T* get() const { return ptr_; }
    size_t size() const { return count_; }

private:
    void release() {
        if (ptr_) cudaFree(ptr_);  // errors here cannot be reported from a destructor
        ptr_ = nullptr;
        count_ = 0;
    }
    T* ptr_ = nullptr;
    size_t count_ = 0;
};

}  // namespace oct
