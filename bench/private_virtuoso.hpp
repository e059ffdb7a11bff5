#pragma once
// A Virtuoso of a benchmark's own (kb/engine), on a data directory of its own under the
// system's temporary directory: stopped, and the directory removed, when it goes.
#include <filesystem>
#include <memory>
#include <random>
#include <string>

#include "kb/engine/virtuoso_instance.hpp"

namespace skillcell::bench {

class PrivateVirtuoso {
public:
    /// Started, or null with `error` set. `name` goes into the directory's name.
    static std::unique_ptr<PrivateVirtuoso> start(const std::string& name, std::string* error) {
        std::random_device rd;
        auto v = std::make_unique<PrivateVirtuoso>(std::filesystem::temp_directory_path() /
                                                   (name + "-" + std::to_string(rd())));
        if (auto s = v->instance_->start(); !s) {
            *error = "Virtuoso: " + s.error();
            return nullptr;
        }
        return v;
    }
    /// Not started: start() is the way in.
    explicit PrivateVirtuoso(std::filesystem::path dir) : dir_(std::move(dir)) {
        kb::engine::VirtuosoConfig config;
        config.dataDir = dir_;
        instance_ = std::make_unique<kb::engine::VirtuosoInstance>(config);
    }
    ~PrivateVirtuoso() {
        (void)instance_->stop();
        instance_.reset();
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    PrivateVirtuoso(const PrivateVirtuoso&) = delete;
    PrivateVirtuoso& operator=(const PrivateVirtuoso&) = delete;

    [[nodiscard]] const kb::engine::VirtuosoInstance& instance() const { return *instance_; }

private:
    std::filesystem::path dir_;
    std::unique_ptr<kb::engine::VirtuosoInstance> instance_;
};

}  // namespace skillcell::bench
