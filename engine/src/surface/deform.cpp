// Regathering the textures of a deforming mesh from the bake's piece table (deform.h).
//
// Every entry is a sum over its pieces, independent of all other entries, so entries are split
// into chunks and the chunks shared out to worker threads. The threads are started once and
// kept: regathering is per frame, and starting a dozen threads costs about as much as the
// regather itself at N = 512.
#include "plimsoll/surface/deform.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace plimsoll {

namespace {

/// Entries a chunk: large enough that taking a chunk costs nothing next to computing it.
constexpr std::size_t kChunkEntries = 4096;
/// Below this many entries the calling thread alone is faster than waking the workers.
constexpr std::size_t kMinParallelEntries = 4 * kChunkEntries;

/// Worker threads that run the chunks of one job at a time, with the calling thread.
class WorkerPool {
public:
    using Work = void (*)(const void* context, std::size_t chunk);

    explicit WorkerPool(unsigned workers) {
        for (unsigned i = 0; i < workers; ++i) threads_.emplace_back([this] { serve(); });
    }

    ~WorkerPool() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : threads_) t.join();
    }

    /// Runs work(context, c) for every chunk c in [0, chunks) and returns when all are done;
    /// false, having run nothing, when another call holds the pool.
    bool tryRun(std::size_t chunks, Work work, const void* context) {
        std::unique_lock<std::mutex> call(callMutex_, std::try_to_lock);
        if (!call.owns_lock()) return false;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            work_ = work;
            context_ = context;
            chunks_ = chunks;
            nextChunk_ = 0;
            busyWorkers_ = threads_.size();
            ++generation_;
        }
        wake_.notify_all();
        runChunks();
        // The job's context lives on the caller's stack: wait until no worker can touch it.
        std::unique_lock<std::mutex> lock(mutex_);
        done_.wait(lock, [this] { return busyWorkers_ == 0; });
        return true;
    }

private:
    void runChunks() {
        for (std::size_t c = nextChunk_++; c < chunks_; c = nextChunk_++) work_(context_, c);
    }

    void serve() {
        std::uint64_t seen = 0;
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            lock.unlock();
            runChunks();
            lock.lock();
            if (--busyWorkers_ == 0) done_.notify_one();
        }
    }

    std::vector<std::thread> threads_;
    std::mutex callMutex_;  ///< held by the call whose job the pool runs
    std::mutex mutex_;      ///< guards the job description and the counters below
    std::condition_variable wake_, done_;
    Work work_ = nullptr;
    const void* context_ = nullptr;
    std::size_t chunks_ = 0;
    std::atomic<std::size_t> nextChunk_{0};
    std::size_t busyWorkers_ = 0;
    std::uint64_t generation_ = 0;
    bool stop_ = false;
};

WorkerPool& regatherPool() {
    static WorkerPool pool(std::max(1u, std::thread::hardware_concurrency()) - 1);
    return pool;
}

struct RegatherJob {
    const SurfacePieceTable* table;
    const TriangleMesh* mesh;
    SurfaceTextures* textures;
};

/// The bake's arithmetic (bake.cpp: prepareTriangles, addPiece, TexelAccumulator::add,
/// collect), step for step, so the undeformed mesh gives the bake back bit for bit.
void regatherEntries(const RegatherJob& job, std::size_t begin, std::size_t end) {
    const std::vector<SurfacePiece>& pieces = job.table->pieces;
    const std::vector<Eigen::Vector3d>& positions = job.mesh->positions;
    SurfaceTextures& out = *job.textures;
    for (std::size_t e = begin; e < end; ++e) {
        Eigen::Vector3d areaVector = Eigen::Vector3d::Zero();
        Eigen::Vector3d weightedPosition = Eigen::Vector3d::Zero();
        Eigen::Vector3d firstCentroid = Eigen::Vector3d::Zero();
        double area = 0;
        const std::uint32_t first = job.table->firstPiece[e];
        const std::uint32_t last = job.table->firstPiece[e + 1];
        for (std::uint32_t i = first; i < last; ++i) {
            const SurfacePiece& piece = pieces[i];
            const Triangle& t = job.mesh->triangles[piece.triangle];
            const Eigen::Vector3d origin = positions[t[0]];
            const Eigen::Vector3d side1 = positions[t[1]] - origin;
            const Eigen::Vector3d side2 = positions[t[2]] - origin;
            const Eigen::Vector3d triangleAreaVector = 0.5 * side1.cross(side2);
            const Eigen::Vector3d pieceAreaVector = piece.share * triangleAreaVector;
            const double pieceArea = piece.share * triangleAreaVector.norm();
            const Eigen::Vector3d centroid =
                origin + piece.barycentric[0] * side1 + piece.barycentric[1] * side2;
            areaVector += pieceAreaVector;
            area += pieceArea;
            weightedPosition += pieceArea * centroid;
            if (i == first) firstCentroid = centroid;
        }
        out.areaVector[e] = areaVector;
        out.area[e] = area;
        // A frame may squash an entry's surface flat (zero area): keep a point on it.
        out.position[e] = area > 0 ? Eigen::Vector3d(weightedPosition / area) : firstCentroid;
    }
}

void regatherChunk(const void* context, std::size_t chunk) {
    const auto& job = *static_cast<const RegatherJob*>(context);
    const std::size_t begin = chunk * kChunkEntries;
    regatherEntries(job, begin, std::min(begin + kChunkEntries, job.textures->coveredCount()));
}

}  // namespace

void regatherSurface(const SurfacePieceTable& table, const TriangleMesh& deformed,
                     SurfaceTextures& textures) {
    assert(deformed.triangleCount() == table.triangleCount);
    assert(table.entryCount() == textures.coveredCount());
    assert(textures.position.size() == textures.coveredCount() &&
           textures.areaVector.size() == textures.coveredCount() &&
           textures.area.size() == textures.coveredCount());
    const RegatherJob job{&table, &deformed, &textures};
    const std::size_t entries = textures.coveredCount();
    if (entries >= kMinParallelEntries &&
        regatherPool().tryRun((entries + kChunkEntries - 1) / kChunkEntries, regatherChunk, &job))
        return;
    regatherEntries(job, 0, entries);
}

}  // namespace plimsoll
